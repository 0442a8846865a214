// The probe's training loss: against a dense reference (the BFGS update of A^-1 written out),
// against pqn itself run for K iterations on the step's quadratic model and on its energy, its
// derivative against central differences on both, zero along the Newton step, never higher with
// more iterations, blind to the scale and sign of the proposal, and the layout of the free dofs.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include <fnopt/baselines/first_order.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/training/probe_loss.hpp>
#include "tests/util/falling_cloth_step.hpp"

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

ProbeLossOptions scoring(int iterations, ProbeSurface surface = ProbeSurface::QuadraticModel) {
  ProbeLossOptions options;
  options.iterations = iterations;
  options.surface = surface;
  return options;
}

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
  const Eigen::MatrixXd A =
      dense(build_pqn_matrix(step.objective, step.handles.free_index(), step.grid.rest_positions()).expanded());
  const VecX& g = loss.gradient();
  const Eigen::MatrixXd A_inverse = A.inverse();
  const double best = -0.5 * g.dot(H.ldlt().solve(g));
  auto remaining_of = [&](const VecX& d) { return 1.0 - (g.dot(d) + 0.5 * d.dot(H * d)) / best; };

  const torch::Tensor p = step.random_free(loss);
  const VecX q = to_vec(p);
  const VecX s = -(g.dot(q) / q.dot(A * q)) * q, y = H * s;
  const double rho = 1.0 / s.dot(y);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(g.size(), g.size());
  const Eigen::MatrixXd H1 =
      (I - rho * s * y.transpose()) * A_inverse * (I - rho * y * s.transpose()) + rho * s * s.transpose();
  EXPECT_NEAR(loss.remaining(p).item<double>(), remaining_of(-H1 * g), 1e-9);
  EXPECT_NEAR(loss.remaining_without_probe(), remaining_of(-A_inverse * g), 1e-9);
  // Where H differs from A, pqn's first step leaves a visible part of the decrease.
  EXPECT_GT(loss.remaining_without_probe(), 1e-3);
}

TEST(ProbeLoss, AgreesWithPqnRunOnTheQuadraticModel) {
  // pqn (baselines/pqn.cpp) on m(d) = g.d + d.H d / 2 over the free dofs, the probe's pair added
  // from outside before its first iteration: after K iterations m is (1 - R) m*, with K = 7
  // running past the iteration where pqn's 5-pair history lets the probe's pair go.
  DeformedStep step;
  const std::vector<int>& free_index = step.handles.free_index();
  const Eigen::SparseMatrix<double> lower = step.objective.hessian(step.a, free_index, true);
  const Eigen::SparseMatrix<double> H = lower.selfadjointView<Eigen::Lower>();
  const PqnMatrix matrix = build_pqn_matrix(step.objective, free_index, step.grid.rest_positions());
  auto to_free = [&](const VecX& full) {
    VecX free(H.rows());
    for (int v = 0; v < step.grid.vertex_count(); ++v)
      if (free_index[v] >= 0) free.segment<3>(3 * free_index[v]) = full.segment<3>(3 * v);
    return free;
  };
  auto to_full = [&](const VecX& free) {
    VecX full = VecX::Zero(step.grid.dof_count());
    for (int v = 0; v < step.grid.vertex_count(); ++v)
      if (free_index[v] >= 0) full.segment<3>(3 * v) = free.segment<3>(3 * free_index[v]);
    return full;
  };
  const ProbeLoss one(step.problem, step.a, step.gradient);
  const VecX g = one.gradient();
  FunctionSmoothProblem model(step.grid.dof_count(), [&](const VecX& x, VecX* gradient) {
    const VecX d = to_free(x), Hd = H * d;
    if (gradient) *gradient = to_full(g + Hd);
    return g.dot(d) + 0.5 * d.dot(Hd);
  });
  const double best = -0.5 * g.dot(Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(H).solve(g));
  const torch::Tensor p = step.random_free(one);
  const VecX q = to_vec(p);
  const VecX s = -(g.dot(q) / q.dot(matrix.expanded().selfadjointView<Eigen::Lower>() * q)) * q;
  for (const int iterations : {1, 3, 7}) {
    const ProbeLoss loss(step.problem, step.a, step.gradient, scoring(iterations));
    for (const bool with_probe : {false, true}) {
      PqnOptimizer pqn;
      pqn.use_matrix(matrix);
      VecX x = VecX::Zero(step.grid.dof_count()), gradient;
      double value = model.value_gradient(x, gradient);
      pqn.begin(model, x, value, gradient);
      if (with_probe) {
        ASSERT_TRUE(pqn.add_pair(x, gradient, to_full(s), to_full(g + H * s)));
      }
      for (int k = 0; k < iterations; ++k) ASSERT_FALSE(pqn.step(model, x, value, gradient).has_value());
      const double remaining = with_probe ? loss.remaining(p).item<double>() : loss.remaining_without_probe();
      EXPECT_NEAR(remaining, 1.0 - value / best, 1e-8) << iterations << " iterations, probe " << with_probe;
    }
  }
}

TEST(ProbeLoss, MoreIterationsNeverLeaveMore) {
  DeformedStep step;
  const torch::Tensor p = step.random_free(ProbeLoss(step.problem, step.a, step.gradient));
  double previous = 1.0, previous_alone = 1.0;
  for (int iterations = 1; iterations <= 8; ++iterations) {
    const ProbeLoss loss(step.problem, step.a, step.gradient, scoring(iterations));
    const double r = loss.remaining(p).item<double>(), alone = loss.remaining_without_probe();
    EXPECT_LE(r, previous + 1e-12) << iterations;
    EXPECT_LE(alone, previous_alone + 1e-12) << iterations;
    previous = r, previous_alone = alone;
  }
  EXPECT_LT(previous, 0.5 * ProbeLoss(step.problem, step.a, step.gradient).remaining(p).item<double>());
}

TEST(ProbeLoss, OnTheEnergyAgreesWithPqnRunOnTheStep) {
  // pqn on the cloth step itself, the probe's pair (a -> a + s, the gradients there) added before
  // its first iteration: the per-step error after K iterations is R, against a* = Newton's.
  DeformedStep step;
  NewtonOptimizer newton;
  VecX solution = step.a;
  const double best = solve_step(newton, step.problem, solution, NewtonOptimizer::reference_solve_options()).value;
  const ProbeLoss one(step.problem, step.a, step.gradient, scoring(1, ProbeSurface::Energy), &solution);
  ASSERT_TRUE(one.defined());
  const torch::Tensor p = step.random_free(one);
  // s = alpha p on every dof, alpha = -g.p / p.A p.
  const Eigen::SparseMatrix<double> A =
      build_pqn_matrix(step.objective, step.handles.free_index(), step.grid.rest_positions()).expanded();
  const VecX q = to_vec(p);
  const VecX s_free = -(one.gradient().dot(q) / q.dot(A.selfadjointView<Eigen::Lower>() * q)) * q;
  VecX s = VecX::Zero(step.grid.dof_count());
  for (int v = 0, k = 0; v < step.grid.vertex_count(); ++v)
    if (step.handles.free_index()[v] >= 0)
      for (int c = 0; c < 3; ++c) s[3 * v + c] = s_free[k++];
  ClothSmoothProblem cloth(step.problem);
  for (const int iterations : {1, 3, 7}) {
    const ProbeLoss loss(step.problem, step.a, step.gradient, scoring(iterations, ProbeSurface::Energy), &solution);
    for (const bool with_probe : {false, true}) {
      PqnOptimizer pqn;
      VecX a = step.a, gradient = step.gradient, probed_gradient;
      double value = step.value;
      pqn.begin(cloth, a, value, gradient);
      if (with_probe) {
        cloth.value_gradient(a + s, probed_gradient);
        ASSERT_TRUE(pqn.add_pair(a, gradient, a + s, probed_gradient));
      }
      for (int k = 0; k < iterations; ++k) ASSERT_FALSE(pqn.step(cloth, a, value, gradient).has_value());
      const double remaining = with_probe ? loss.remaining(p).item<double>() : loss.remaining_without_probe();
      EXPECT_NEAR(remaining, (value - best) / (step.value - best), 1e-7)
          << iterations << " iterations, probe " << with_probe;
      if (iterations == 7) {
        EXPECT_LT(remaining, 0.3) << "pqn closes in on the step's solution";
      }
    }
  }
  EXPECT_THROW(static_cast<void>(ProbeLoss(step.problem, step.a, step.gradient, scoring(1, ProbeSurface::Energy))),
               Error)
      << "the energy surface needs the solution";
}

TEST(ProbeLoss, DerivativeMatchesCentralDifferences) {
  DeformedStep step;
  NewtonOptimizer newton;
  VecX solution = step.a;
  solve_step(newton, step.problem, solution, NewtonOptimizer::reference_solve_options());
  for (const auto& [iterations, surface] : std::vector<std::pair<int, ProbeSurface>>{
           {1, ProbeSurface::QuadraticModel}, {4, ProbeSurface::QuadraticModel}, {3, ProbeSurface::Energy}}) {
    const ProbeLoss loss(step.problem, step.a, step.gradient, scoring(iterations, surface), &solution);
    const torch::Tensor p = step.random_free(loss).requires_grad_(true);
    const torch::Tensor value = loss.remaining(p);
    value.backward();
    const torch::Tensor v = step.random_free(loss);
    const double eps = 1e-5 * p.norm().item<double>() / v.norm().item<double>();
    const double difference =
        (loss.remaining(p.detach() + eps * v).item<double>() - loss.remaining(p.detach() - eps * v).item<double>()) /
        (2 * eps);
    const double analytic = p.grad().dot(v).item<double>();
    EXPECT_NEAR(analytic, difference, 1e-6 * std::abs(difference) + 1e-9) << iterations << " iterations";
    EXPECT_GT(std::abs(analytic), 1e-6) << iterations << " iterations";
  }
}

TEST(ProbeLoss, TheNewtonDirectionLeavesNothing) {
  DeformedStep step;
  for (const int iterations : {1, 3}) {
    const ProbeLoss loss(step.problem, step.a, step.gradient, scoring(iterations));
    const Eigen::MatrixXd H = dense(step.objective.hessian(step.a, step.handles.free_index(), true));
    const VecX newton = -H.ldlt().solve(loss.gradient());
    const torch::Tensor p = torch::from_blob(const_cast<double*>(newton.data()), {newton.size()}, torch::kFloat64);
    EXPECT_NEAR(loss.remaining(p).item<double>(), 0.0, 1e-9) << iterations << " iterations";
    EXPECT_GT(loss.remaining(step.random_free(loss)).item<double>(), 1e-4) << iterations << " iterations";
  }
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
    for (int c = 0; c < 3; ++c, ++k)
      EXPECT_NEAR(free[k], field[3 * v + c], 1e-5 * std::abs(field[3 * v + c])) << "vertex " << v;
  }
}

}  // namespace
}  // namespace fnopt
