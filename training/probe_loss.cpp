#include "training/probe_loss.hpp"

#include <functional>

#include "util/error.hpp"

namespace fnopt {
namespace {

using LinearMap = std::function<void(VecX&)>;  // v <- M v, M symmetric

torch::Tensor apply_map(const LinearMap& map, const torch::Tensor& x) {
  const torch::Tensor in = x.detach().to(torch::kFloat64).contiguous();
  VecX v = Eigen::Map<const VecX>(in.data_ptr<double>(), in.numel());
  map(v);
  return torch::from_blob(v.data(), {v.size()}, torch::kFloat64).clone();
}

// x -> M x for a symmetric M: its own adjoint, so the backward pass applies M again.
struct SymmetricMap : torch::autograd::Function<SymmetricMap> {
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor x, const LinearMap* map) {
    ctx->saved_data["map"] = reinterpret_cast<int64_t>(map);
    return apply_map(*map, x);
  }
  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs) {
    const auto* map = reinterpret_cast<const LinearMap*>(ctx->saved_data["map"].toInt());
    return {apply_map(*map, grad_outputs[0]), torch::Tensor()};
  }
};

VecX product(const Eigen::SparseMatrix<double>& M, const VecX& v) {
  return M.selfadjointView<Eigen::Lower>() * v;
}

}  // namespace

struct ProbeLoss::Maps {
  LinearMap hessian, matrix, matrix_inverse;
};

ProbeLoss::ProbeLoss(StepProblem& problem, const VecX& a, const VecX& gradient, PqnMatrixKind kind)
    : maps_(std::make_unique<Maps>()) {
  const std::vector<int>& free_index = problem.dirichlet().free_index();
  std::vector<int64_t> dofs;
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v)
    if (free_index[v] >= 0)
      for (int c = 0; c < 3; ++c) dofs.push_back(3 * v + c);
  free_dof_index_ = torch::tensor(dofs, torch::kInt64);

  gradient_.resize(static_cast<Eigen::Index>(dofs.size()));
  for (std::size_t k = 0; k < dofs.size(); ++k) gradient_[static_cast<Eigen::Index>(k)] = gradient[dofs[k]];

  hessian_ = problem.objective().hessian(a, free_index, /*project=*/true);
  matrix_ = build_pqn_matrix(problem.objective(), free_index, kind, problem.grid().rest_positions()).expanded();
  SparseCholesky hessian_factor;  // for m* alone
  require(hessian_factor.factorize_matrix(hessian_), "probe loss", "the projected Hessian is not positive definite");
  require(matrix_factor_.factorize_matrix(matrix_), "probe loss", "pqn's matrix is not positive definite");

  maps_->hessian = [this](VecX& v) { v = product(hessian_, v); };
  maps_->matrix = [this](VecX& v) { v = product(matrix_, v); };
  maps_->matrix_inverse = [this](VecX& v) {
    matrix_factor_.solve_in_place(v.data(), static_cast<int>(v.size()), 1);
  };

  VecX newton = gradient_;
  hessian_factor.solve_in_place(newton.data(), static_cast<int>(newton.size()), 1);
  newton_decrease_ = -0.5 * gradient_.dot(newton);
  VecX pqn = -gradient_;
  maps_->matrix_inverse(pqn);
  const double pqn_decrease = gradient_.dot(pqn) + 0.5 * pqn.dot(product(hessian_, pqn));
  remaining_without_probe_ = newton_decrease_ < 0.0 ? 1.0 - pqn_decrease / newton_decrease_ : 0.0;
}

ProbeLoss::~ProbeLoss() = default;

torch::Tensor ProbeLoss::remaining(const torch::Tensor& p) const {
  require(defined(), "probe loss", "the gradient is zero: no decrease to measure");
  require(p.dim() == 1 && p.size(0) == gradient_.size(), "probe loss", "p must hold the free dofs");
  const torch::Tensor g = torch::from_blob(const_cast<double*>(gradient_.data()), {gradient_.size()}, torch::kFloat64);
  const torch::Tensor q = p.to(torch::kFloat64);
  const torch::Tensor s = -(g.dot(q) / q.dot(SymmetricMap::apply(q, &maps_->matrix))) * q;
  const torch::Tensor y = SymmetricMap::apply(s, &maps_->hessian);
  const torch::Tensor rho = 1.0 / s.dot(y);
  const torch::Tensor c = rho * s.dot(g);
  const torch::Tensor r = SymmetricMap::apply(g - c * y, &maps_->matrix_inverse);
  const torch::Tensor d = -(r + s * (c - rho * y.dot(r)));
  const torch::Tensor decrease = g.dot(d) + 0.5 * d.dot(SymmetricMap::apply(d, &maps_->hessian));
  return 1.0 - decrease / newton_decrease_;
}

torch::Tensor ProbeLoss::free_dofs(const torch::Tensor& coordinate_samples) const {
  return coordinate_samples.squeeze(1).permute({1, 2, 0}).reshape({-1}).to(torch::kFloat64).index_select(
      0, free_dof_index_);
}

}  // namespace fnopt
