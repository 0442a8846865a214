#include <fnopt/training/probe_loss.hpp>

#include <cmath>
#include <functional>

#include <fnopt/baselines/curvature_history.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// A map x -> f(x) whose Jacobian J(x) is symmetric (a symmetric matrix, or the gradient of an
// energy), so that the backward pass applies J(x) to the incoming gradient.
struct SymmetricJacobianMap {
  std::function<void(const VecX& x, VecX& out)> value;   // out <- f(x)
  std::function<void(const VecX& x, VecX& v)> jacobian;  // v <- J(x) v
};

VecX to_vec(const torch::Tensor& x) {
  const torch::Tensor in = x.detach().to(torch::kFloat64).contiguous();
  return Eigen::Map<const VecX>(in.data_ptr<double>(), in.numel());
}

torch::Tensor to_tensor(const VecX& v) {
  return torch::from_blob(const_cast<double*>(v.data()), {v.size()}, torch::kFloat64).clone();
}

struct SymmetricJacobianFunction : torch::autograd::Function<SymmetricJacobianFunction> {
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor x,
                               const SymmetricJacobianMap* map) {
    ctx->saved_data["map"] = reinterpret_cast<int64_t>(map);
    ctx->save_for_backward({x});
    VecX out;
    map->value(to_vec(x), out);
    return to_tensor(out);
  }
  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs) {
    const auto* map = reinterpret_cast<const SymmetricJacobianMap*>(ctx->saved_data["map"].toInt());
    VecX v = to_vec(grad_outputs[0]);
    map->jacobian(to_vec(ctx->get_saved_variables()[0]), v);
    return {to_tensor(v), torch::Tensor()};
  }
};

torch::Tensor apply(const SymmetricJacobianMap& map, const torch::Tensor& x) {
  return SymmetricJacobianFunction::apply(x, &map);
}

// v <- M v for a symmetric M stored as its lower triangle.
void multiply(const Eigen::SparseMatrix<double>& M, VecX& v) { v = M.selfadjointView<Eigen::Lower>() * v; }

SymmetricJacobianMap linear_map(std::function<void(VecX&)> apply_in_place) {
  return {[apply_in_place](const VecX& x, VecX& out) {
            out = x;
            apply_in_place(out);
          },
          [apply_in_place](const VecX&, VecX& v) { apply_in_place(v); }};
}

}  // namespace

void ProbeLossOptions::validate() const {
  require(iterations >= 1 && iterations <= 100, "probe.iterations", "must lie in [1, 100]");
  pqn.validate();
}

struct ProbeLoss::Maps {
  SymmetricJacobianMap hessian, matrix, matrix_inverse, energy_gradient;
};

ProbeLoss::ProbeLoss(const StepProblem& problem, const VecX& a, const VecX& gradient, const ProbeLossOptions& options,
                     const VecX* solution)
    : problem_(problem), options_(options), maps_(std::make_unique<Maps>()), a_(a) {
  options_.validate();
  const bool quadratic = options_.surface == ProbeSurface::QuadraticModel;
  require(quadratic || solution != nullptr, "probe loss", "the energy surface needs the step's Newton solution");
  const std::vector<int>& free_index = problem_.dirichlet().free_index();
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v)
    if (free_index[v] >= 0)
      for (int c = 0; c < 3; ++c) free_dofs_.push_back(3 * v + c);
  free_dof_index_ = torch::tensor(std::vector<int64_t>(free_dofs_.begin(), free_dofs_.end()), torch::kInt64);
  gradient_.resize(static_cast<Eigen::Index>(free_dofs_.size()));
  for (std::size_t k = 0; k < free_dofs_.size(); ++k) gradient_[static_cast<Eigen::Index>(k)] = gradient[free_dofs_[k]];

  matrix_ = build_pqn_matrix(problem_.objective(), free_index, problem_.grid().rest_positions()).expanded();
  require(matrix_factor_.factorize_matrix(matrix_), "probe loss", "pqn's matrix is not positive definite");
  maps_->matrix = linear_map([this](VecX& v) { multiply(matrix_, v); });
  maps_->matrix_inverse =
      linear_map([this](VecX& v) { matrix_factor_.solve_in_place(v.data(), static_cast<int>(v.size()), 1); });

  if (quadratic) {
    hessian_ = problem_.objective().hessian(a, free_index, /*project=*/true);
    SparseCholesky hessian_factor;  // for f* alone
    require(hessian_factor.factorize_matrix(hessian_), "probe loss", "the projected Hessian is not positive definite");
    maps_->hessian = linear_map([this](VecX& v) { multiply(hessian_, v); });
    VecX newton = gradient_;
    hessian_factor.solve_in_place(newton.data(), static_cast<int>(newton.size()), 1);
    start_value_ = 0.0;
    best_value_ = -0.5 * gradient_.dot(newton);
  } else {
    maps_->energy_gradient = {[this](const VecX& d, VecX& out) {
                                VecX full;
                                problem_.value_gradient(at(d), full);
                                out.resize(d.size());
                                for (Eigen::Index k = 0; k < d.size(); ++k) out[k] = full[free_dofs_[k]];
                              },
                              [this](const VecX& d, VecX& v) {
                                multiply(problem_.objective().hessian(at(d), problem_.dirichlet().free_index(),
                                                                      /*project=*/false),
                                         v);
                              }};
    start_value_ = problem_.value(a);
    best_value_ = problem_.value(*solution);
  }
  start_gap_ = start_value_ - best_value_;
  if (defined()) {
    torch::NoGradGuard no_grad;
    remaining_without_probe_ = (surface_after_pqn(torch::Tensor()).item<double>() - best_value_) / start_gap_;
  }
}

ProbeLoss::~ProbeLoss() = default;

VecX ProbeLoss::at(const VecX& d) const {
  VecX full = a_;
  for (Eigen::Index k = 0; k < d.size(); ++k) full[free_dofs_[k]] += d[k];
  return full;
}

double ProbeLoss::surface_value(const VecX& d) const {
  if (options_.surface == ProbeSurface::Energy) return problem_.value(at(d));
  VecX hd = d;
  multiply(hessian_, hd);
  return gradient_.dot(d) + 0.5 * d.dot(hd);
}

torch::Tensor ProbeLoss::remaining(const torch::Tensor& p) const {
  require(defined(), "probe loss", "no decrease left to measure");
  require(p.dim() == 1 && p.size(0) == gradient_.size(), "probe loss", "p must hold the free dofs");
  const torch::Tensor g = torch::from_blob(const_cast<double*>(gradient_.data()), {gradient_.size()}, torch::kFloat64);
  const torch::Tensor q = p.to(torch::kFloat64);
  const torch::Tensor s = -(g.dot(q) / q.dot(apply(maps_->matrix, q))) * q;
  return (surface_after_pqn(s) - best_value_) / start_gap_;
}

torch::Tensor ProbeLoss::surface_after_pqn(const torch::Tensor& probe) const {
  const torch::Tensor g0 = torch::from_blob(const_cast<double*>(gradient_.data()), {gradient_.size()}, torch::kFloat64);
  const bool quadratic = options_.surface == ProbeSurface::QuadraticModel;
  auto gradient_at = [&](const torch::Tensor& d) {
    return quadratic ? g0 + apply(maps_->hessian, d) : apply(maps_->energy_gradient, d);
  };
  // pqn's ring of pairs and its test for a pair (baselines/pqn.cpp), on tensors.
  using TensorHistory = BasicCurvatureHistory<torch::Tensor, torch::Tensor>;
  TensorHistory history(options_.pqn.history);
  auto keep = [&](const torch::Tensor& s, const torch::Tensor& y) {
    history.push_pair(s, y, [](const TensorHistory::Pair& pair, const torch::Tensor& sy) {
      return clearly_positive_curvature(sy.item<double>(),
                                        pair.s.norm().item<double>() * pair.y.norm().item<double>());
    });
  };
  if (probe.defined()) keep(probe, gradient_at(probe) - g0);

  const BacktrackingParams& search = options_.pqn.line_search;
  torch::Tensor d = torch::zeros({gradient_.size()}, torch::kFloat64), g = g0;
  double value = start_value_;
  std::vector<torch::Tensor> alphas;
  for (int k = 0; k < options_.iterations; ++k) {
    // The two-loop recursion on A^-1; pqn restarts from -A^-1 g where rounding leaves it no descent.
    torch::Tensor direction;
    double slope = 0.0;
    if (history.size() > 0) {
      lbfgs_two_loop(
          history.oldest_first(), [&](torch::Tensor& q) { q = apply(maps_->matrix_inverse, q); }, g, direction,
          alphas);
      slope = g.dot(direction).item<double>();
      if (!(std::isfinite(slope) && slope < 0.0)) history.clear();
    }
    if (history.size() == 0) {
      direction = -apply(maps_->matrix_inverse, g);
      slope = g.dot(direction).item<double>();
    }
    // pqn's backtracking (optimizer/line_search.hpp) from the unit step; its step length is
    // piecewise constant in p, so no derivative flows through it. Values only, no gradient per
    // trial; without that search's acceptance below L's rounding floor, where R has nothing left
    // to measure.
    const VecX from = to_vec(d), along = to_vec(direction);
    double t = 1.0, trial_value = value;
    bool accepted = false;
    for (int trial = 0; trial < search.max_trials; ++trial, t *= search.shrink) {
      trial_value = surface_value(from + t * along);
      accepted = std::isfinite(trial_value) && trial_value < value && trial_value <= value + search.armijo * t * slope;
      if (accepted) break;
    }
    if (!accepted) break;  // pqn stops where no step lowers f
    const torch::Tensor next = d + t * direction;
    const torch::Tensor next_gradient = gradient_at(next);
    keep(next - d, next_gradient - g);
    d = next, g = next_gradient, value = trial_value;
  }
  // f(d_K), differentiable in d_K: on the quadratic model exactly, g(d) = g0 + H d making it
  // d.(g0 + g(d)) / 2; on the energy to first order, with df/dd = g(d_K).
  if (quadratic) return 0.5 * d.dot(g0 + g);
  return value + g.detach().dot(d - d.detach());
}

torch::Tensor ProbeLoss::free_dofs(const torch::Tensor& coordinate_samples) const {
  return coordinate_samples.squeeze(1)
      .permute({1, 2, 0})
      .reshape({-1})
      .to(torch::kFloat64)
      .index_select(0, free_dof_index_);
}

}  // namespace fnopt
