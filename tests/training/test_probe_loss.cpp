// The probe's training loss: against a dense reference (the BFGS update of A^-1 written out),
// its derivative against central differences, zero along the Newton step, blind to the scale
// and sign of the proposal, and the layout of the free dofs.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "training/probe_loss.hpp"
#include "tests/optimizer/learned/falling_cloth_step.hpp"

namespace fnopt {
namespace {

// The falling cloth part-way into its step, where the Hessian is no longer pqn's matrix.
struct DeformedStep : FallingClothStep {
  std::mt19937_64 rng{11};
  DeformedStep() {
    a = -0.7 * gradient_step_length() * gradient + random_field(0.3 * gradient_step_length() * gradient.norm());
    value = problem.value_gradient(a, gradient);
  }
  VecX random_field(double norm) {
    std::normal_distribution<double> normal;
    VecX v(grid.dof_count());
    for (auto& x : v) x = normal(rng);
    handles.zero_fixed(v);
    return v * (norm / v.norm());
  }
  torch::Tensor random_free(const ProbeLoss& loss) {
    return loss.free_dofs(to_coordinate_samples(random_field(1.0), grid).to(torch::kFloat64));
  }
};

Eigen::MatrixXd dense(const Eigen::SparseMatrix<double>& M) {
  const Eigen::SparseMatrix<double> full = M.selfadjointView<Eigen::Lower>();
  return Eigen::MatrixXd(full);
}

VecX to_vec(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat64).contiguous();
  return Eigen::Map<const VecX>(c.data_ptr<double>(), c.numel());
}

TEST(ProbeLoss, AgreesWithTheDenseBfgsUpdate) {
  DeformedStep step;
  const ProbeLoss loss(step.problem, step.a, step.gradient);
  ASSERT_TRUE(loss.defined());
  const Eigen::MatrixXd H = dense(step.objective.hessian(step.a, step.handles.free_index(), true));
  const Eigen::MatrixXd A = dense(
      build_pqn_matrix(step.objective, step.handles.free_index(), PqnMatrixKind::Isotropic, step.grid.rest_positions())
          .expanded());
  const VecX& g = loss.gradient();
  const Eigen::MatrixXd A_inverse = A.inverse();
  const double best = -0.5 * g.dot(H.ldlt().solve(g));
  auto remaining_of = [&](const VecX& d) { return 1.0 - (g.dot(d) + 0.5 * d.dot(H * d)) / best; };

  const torch::Tensor p = step.random_free(loss);
  const VecX q = to_vec(p);
  const VecX s = -(g.dot(q) / q.dot(A * q)) * q, y = H * s;
  const double rho = 1.0 / s.dot(y);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(g.size(), g.size());
  const Eigen::MatrixXd H1 = (I - rho * s * y.transpose()) * A_inverse * (I - rho * y * s.transpose()) + rho * s * s.transpose();
  EXPECT_NEAR(loss.remaining(p).item<double>(), remaining_of(-H1 * g), 1e-9);
  EXPECT_NEAR(loss.remaining_without_probe(), remaining_of(-A_inverse * g), 1e-9);
  // Where H differs from A, pqn's first step leaves a visible part of the decrease.
  EXPECT_GT(loss.remaining_without_probe(), 1e-3);
}

TEST(ProbeLoss, DerivativeMatchesCentralDifferences) {
  DeformedStep step;
  const ProbeLoss loss(step.problem, step.a, step.gradient);
  const torch::Tensor p = step.random_free(loss).requires_grad_(true);
  const torch::Tensor value = loss.remaining(p);
  value.backward();
  const torch::Tensor v = step.random_free(loss);
  const double eps = 1e-5 * p.norm().item<double>() / v.norm().item<double>();
  const double difference =
      (loss.remaining(p.detach() + eps * v).item<double>() - loss.remaining(p.detach() - eps * v).item<double>()) /
      (2 * eps);
  const double analytic = p.grad().dot(v).item<double>();
  EXPECT_NEAR(analytic, difference, 1e-6 * std::abs(difference) + 1e-9);
  EXPECT_GT(std::abs(analytic), 1e-6);
}

TEST(ProbeLoss, TheNewtonDirectionLeavesNothing) {
  DeformedStep step;
  const ProbeLoss loss(step.problem, step.a, step.gradient);
  const Eigen::MatrixXd H = dense(step.objective.hessian(step.a, step.handles.free_index(), true));
  const VecX newton = -H.ldlt().solve(loss.gradient());
  const torch::Tensor p = torch::from_blob(const_cast<double*>(newton.data()), {newton.size()}, torch::kFloat64);
  EXPECT_NEAR(loss.remaining(p).item<double>(), 0.0, 1e-9);
  EXPECT_GT(loss.remaining(step.random_free(loss)).item<double>(), 1e-3);
}

TEST(ProbeLoss, BlindToTheScaleAndSignOfTheProposal) {
  DeformedStep step;
  const ProbeLoss loss(step.problem, step.a, step.gradient);
  const torch::Tensor p = step.random_free(loss);
  const double r = loss.remaining(p).item<double>();
  EXPECT_NEAR(loss.remaining(-3.0 * p).item<double>(), r, 1e-12);
  EXPECT_NEAR(loss.remaining(1e-3 * p).item<double>(), r, 1e-12);
}

TEST(ProbeLoss, FreeDofsSkipTheHandles) {
  DeformedStep step;
  const ProbeLoss loss(step.problem, step.a, step.gradient);
  const VecX field = step.random_field(1.0) + VecX::Constant(step.grid.dof_count(), 2.0);
  const VecX free = to_vec(loss.free_dofs(to_coordinate_samples(field, step.grid)));
  ASSERT_EQ(free.size(), 3 * (step.grid.vertex_count() - 2));
  int k = 0;
  for (int v = 0; v < step.grid.vertex_count(); ++v) {
    if (step.handles.free_index()[v] < 0) continue;
    for (int c = 0; c < 3; ++c, ++k) EXPECT_NEAR(free[k], field[3 * v + c], 1e-5 * std::abs(field[3 * v + c])) << "vertex " << v;
  }
}

}  // namespace
}  // namespace fnopt
