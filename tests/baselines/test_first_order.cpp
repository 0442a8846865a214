// The classical inner optimizers (GD, Adam, L-BFGS with and without line search) on analytic
// problems and on real cloth steps: descent, convergence, the two-loop recursion against dense
// BFGS, the handles never moving, parameter validation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <fnopt/baselines/adam.hpp>
#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/lbfgs.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include "tests/util/cloth_step.hpp"

namespace fnopt {
namespace {

// f(x) = 1/2 (x - x*)^T A (x - x*) with a fixed SPD A of condition ~50.
struct Quadratic {
  Eigen::MatrixXd A;
  VecX minimiser;
  explicit Quadratic(int n) {
    std::mt19937 random(3);
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::MatrixXd Q(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) Q(i, j) = normal(random);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(Q);
    const Eigen::MatrixXd U = qr.householderQ();
    VecX eigenvalues(n);
    for (int i = 0; i < n; ++i) eigenvalues[i] = std::pow(50.0, static_cast<double>(i) / (n - 1));
    A = U * eigenvalues.asDiagonal() * U.transpose();
    minimiser.resize(n);
    for (int i = 0; i < n; ++i) minimiser[i] = normal(random);
  }
  double operator()(const VecX& x, VecX* gradient) const {
    const VecX r = x - minimiser;
    if (gradient) *gradient = A * r;
    return 0.5 * r.dot(A * r);
  }
};

// The 2-D Rosenbrock function, minimum 0 at (1, 1).
double rosenbrock(const VecX& x, VecX* gradient) {
  const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
  if (gradient) {
    gradient->resize(2);
    (*gradient)[0] = -2.0 * a - 400.0 * x[0] * b;
    (*gradient)[1] = 200.0 * b;
  }
  return a * a + 100.0 * b * b;
}

struct RunResult {
  double initial_value, value, initial_gradient_norm, gradient_norm;
  int iterations;
  VecX x;
};

// Runs `optimizer` on `problem` from x0 for at most `iterations` or to ||g|| <= tol ||g_0||.
RunResult run(FirstOrderOptimizer& optimizer, SmoothProblem& problem, VecX x, int iterations, double tolerance = 0.0) {
  VecX gradient;
  double value = problem.value_gradient(x, gradient);
  RunResult result{value, value, gradient.norm(), gradient.norm(), 0, x};
  optimizer.begin(problem, x, value, gradient);
  for (int k = 0; k < iterations; ++k) {
    if (gradient.norm() <= tolerance * result.initial_gradient_norm) break;
    if (optimizer.step(problem, x, value, gradient)) break;
    ++result.iterations;
  }
  result.value = value;
  result.gradient_norm = gradient.norm();
  result.x = x;
  return result;
}

template <class F>
auto problem_of(int n, F f) {
  return FunctionSmoothProblem<F>(n, std::move(f));
}

TEST(GradientDescent, DecreasesAQuadraticToItsMinimiser) {
  const Quadratic q(20);
  auto problem = problem_of(20, [&](const VecX& x, VecX* g) { return q(x, g); });
  GradientDescentOptimizer gd;  // step 1/lambda_max from power iteration
  const RunResult r = run(gd, problem, VecX::Zero(20), 2000);
  EXPECT_NEAR(gd.curvature(), 50.0, 5.0);  // the largest eigenvalue of A
  EXPECT_LT(r.value, 1e-10 * r.initial_value);
  EXPECT_LT((r.x - q.minimiser).norm(), 1e-5);
}

TEST(GradientDescent, DecreasesRosenbrockMonotonically) {
  auto problem = problem_of(2, rosenbrock);
  GradientDescentOptimizer gd;
  VecX x(2);
  x << -1.2, 1.0;
  VecX gradient;
  double value = problem.value_gradient(x, gradient);
  const double initial = value;
  gd.begin(problem, x, value, gradient);
  for (int k = 0; k < 2000; ++k) {
    const double before = value;
    gd.step(problem, x, value, gradient);
    ASSERT_LE(value, before + 1e-12) << "iteration " << k;
  }
  EXPECT_LT(value, 1e-2 * initial);
}

TEST(Adam, DecreasesAQuadraticAndRosenbrock) {
  const Quadratic q(20);
  auto quadratic = problem_of(20, [&](const VecX& x, VecX* g) { return q(x, g); });
  AdamParams params;
  params.learning_rate = 0.01;
  AdamOptimizer adam(params);
  const RunResult r = run(adam, quadratic, VecX::Zero(20), 3000);
  EXPECT_LT(r.value, 1e-4 * r.initial_value);

  auto banana = problem_of(2, rosenbrock);
  AdamOptimizer adam2(params);
  VecX x0(2);
  x0 << -1.2, 1.0;
  const RunResult b = run(adam2, banana, x0, 5000);
  EXPECT_LT(b.value, 1e-3 * b.initial_value);
  EXPECT_LT((b.x - VecX::Ones(2)).norm(), 0.1);
}

TEST(Lbfgs, WithLineSearchConvergesTo1e8OnAQuadraticAndRosenbrock) {
  LbfgsParams params;
  params.line_search = true;
  const Quadratic q(30);
  auto quadratic = problem_of(30, [&](const VecX& x, VecX* g) { return q(x, g); });
  LbfgsOptimizer lbfgs(params);
  const RunResult r = run(lbfgs, quadratic, VecX::Zero(30), 500, 1e-8);
  EXPECT_LE(r.gradient_norm, 1e-8 * r.initial_gradient_norm);
  EXPECT_LT((r.x - q.minimiser).norm(), 1.01e-8 * r.initial_gradient_norm);  // lambda_min(A) = 1
  EXPECT_LT(r.iterations, 100);

  auto banana = problem_of(2, rosenbrock);
  LbfgsOptimizer lbfgs2(params);
  VecX x0(2);
  x0 << -1.2, 1.0;
  const RunResult b = run(lbfgs2, banana, x0, 500, 1e-8);
  EXPECT_LE(b.gradient_norm, 1e-8 * b.initial_gradient_norm);
  EXPECT_LT((b.x - VecX::Ones(2)).norm(), 1e-6);
  std::printf("L-BFGS + strong Wolfe: quadratic %d iterations, Rosenbrock %d iterations (%ld evaluations)\n",
              r.iterations, b.iterations, banana.evaluations);
}

TEST(Lbfgs, FixedStepConvergesOnAQuadratic) {
  const Quadratic q(30);
  auto quadratic = problem_of(30, [&](const VecX& x, VecX* g) { return q(x, g); });
  LbfgsOptimizer lbfgs;  // fixed step 1, the paper's variant
  const RunResult r = run(lbfgs, quadratic, VecX::Zero(30), 500, 1e-8);
  EXPECT_LE(r.gradient_norm, 1e-8 * r.initial_gradient_norm);
}

// The two-loop recursion equals the dense BFGS inverse-Hessian update applied pair by pair:
// H <- (I - rho s y^T) H (I - rho y s^T) + rho s s^T, from the same diagonal H0.
TEST(Lbfgs, TwoLoopDirectionEqualsDenseBfgs) {
  const int n = 8;
  const Quadratic q(n);
  std::mt19937 random(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<CurvaturePair> pairs(5);
  for (auto& pair : pairs) {
    pair.s.resize(n);
    for (int i = 0; i < n; ++i) pair.s[i] = normal(random);
    pair.y = q.A * pair.s;  // exact curvature pairs of the quadratic
    pair.rho = 1.0 / pair.s.dot(pair.y);
  }
  VecX h0(n), gradient(n);
  for (int i = 0; i < n; ++i) h0[i] = 0.5 + 0.1 * i, gradient[i] = normal(random);
  std::vector<const CurvaturePair*> ordered;
  for (const auto& pair : pairs) ordered.push_back(&pair);
  VecX direction;
  std::vector<double> scratch;
  lbfgs_two_loop(
      ordered, [&](VecX& q) { q.array() *= h0.array(); }, gradient, direction, scratch);

  Eigen::MatrixXd H = h0.asDiagonal();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  for (const auto& pair : pairs) {
    const Eigen::MatrixXd V = I - pair.rho * pair.y * pair.s.transpose();
    H = V.transpose() * H * V + pair.rho * pair.s * pair.s.transpose();
  }
  const VecX dense = -H * gradient;
  EXPECT_LT((direction - dense).norm(), 1e-12 * dense.norm());
  // With n independent exact pairs, BFGS recovers the inverse Hessian on their span.
  EXPECT_LT(direction.dot(gradient), 0.0);
}

// The pair test of L-BFGS and pqn: a cosine between s and y above 1e-10, finite.
TEST(CurvatureHistory, KeepsOnlyPairsOfClearlyPositiveCurvature) {
  EXPECT_TRUE(clearly_positive_curvature(1.0, 2.0));
  EXPECT_TRUE(clearly_positive_curvature(3e-10, 1.0));
  EXPECT_FALSE(clearly_positive_curvature(1e-10, 1.0));  // at the bound: not clearly positive
  EXPECT_FALSE(clearly_positive_curvature(0.0, 1.0));
  EXPECT_FALSE(clearly_positive_curvature(-1.0, 1.0));
  EXPECT_FALSE(clearly_positive_curvature(std::nan(""), 1.0));
  EXPECT_FALSE(clearly_positive_curvature(std::numeric_limits<double>::infinity(), 1.0));

  CurvatureHistory history(2);
  const VecX x0 = VecX::Zero(2), s = VecX::Unit(2, 0);
  const auto test = [](const CurvaturePair& pair, double sy) {
    return clearly_positive_curvature(sy, pair.s.norm() * pair.y.norm());
  };
  EXPECT_FALSE(history.push(x0, x0, s, -s, test));  // negative curvature: the history stays empty
  EXPECT_EQ(history.size(), 0);
  EXPECT_TRUE(history.push(x0, x0, s, 2.0 * s, test));
  EXPECT_EQ(history.size(), 1);
  EXPECT_DOUBLE_EQ(history.newest().rho, 0.5);
}

TEST(FirstOrderOptimizers, NeverMoveAHandleAndDecreaseARealClothStep) {
  ClothStep step;
  NewtonOptimizer newton;
  VecX a_star = step.a;
  const double best = solve_step(newton, step.problem, a_star, NewtonOptimizer::reference_solve_options()).value;

  AdamParams adam_params;
  adam_params.learning_rate = 1e-3;
  LbfgsParams ls;
  ls.line_search = true;
  std::vector<std::unique_ptr<InnerOptimizer>> optimizers;
  optimizers.push_back(std::make_unique<GradientDescentOptimizer>());
  optimizers.push_back(std::make_unique<AdamOptimizer>(adam_params));
  optimizers.push_back(std::make_unique<LbfgsOptimizer>());
  optimizers.push_back(std::make_unique<LbfgsOptimizer>(ls));
  for (auto& optimizer : optimizers) {
    VecX a = step.a;
    const InnerSolveResult r = solve_step(*optimizer, step.problem, a, {100, 0.0});
    for (int h : step.handles.fixed_vertices())
      EXPECT_EQ(a.segment<3>(3 * h), step.a.segment<3>(3 * h)) << optimizer->name() << " moved handle " << h;
    EXPECT_NE(r.status, SolveStatus::NonFinite) << optimizer->name();
    EXPECT_LT(r.value, r.initial_value) << optimizer->name();
    const double error = (r.value - best) / (r.initial_value - best);
    std::printf("%-9s 100 iterations: per-step error %.3g (%s)\n", optimizer->name().c_str(), error,
                to_string(r.status));
    EXPECT_LT(error, 1.0) << optimizer->name();
  }
}

TEST(FirstOrderOptimizers, LbfgsWithLineSearchReachesTheNewtonStep) {
  ClothStep step;
  NewtonOptimizer newton;
  VecX a_star = step.a;
  solve_step(newton, step.problem, a_star, NewtonOptimizer::reference_solve_options());
  LbfgsParams ls;
  ls.line_search = true;
  LbfgsOptimizer lbfgs(ls);
  VecX a = step.a;
  const InnerSolveResult r = solve_step(lbfgs, step.problem, a, {3000, 1e-6});
  std::printf("L-BFGS + line search on a 12x12 cloth step: %d iterations to 1e-6, %ld trials\n", r.iterations,
              lbfgs.line_search_evaluations());
  EXPECT_EQ(r.status, SolveStatus::Converged);
  EXPECT_LT((a - a_star).norm(), 1e-3 * a_star.norm());
}

TEST(FirstOrderOptimizers, ParametersAreValidated) {
  GradientDescentParams gd;
  gd.learning_rate = -1.0;
  EXPECT_ANY_THROW(GradientDescentOptimizer{gd});
  AdamParams adam;
  adam.beta2 = 1.0;
  EXPECT_ANY_THROW(AdamOptimizer{adam});
  LbfgsParams lbfgs;
  lbfgs.history = 0;
  EXPECT_ANY_THROW(LbfgsOptimizer{lbfgs});
  lbfgs = LbfgsParams{};
  lbfgs.wolfe.c2 = lbfgs.wolfe.c1 / 2;
  EXPECT_ANY_THROW(LbfgsOptimizer{lbfgs});
  EXPECT_EQ(LbfgsOptimizer{}.name(), "lbfgs");
  lbfgs = LbfgsParams{};
  lbfgs.line_search = true;
  EXPECT_EQ(LbfgsOptimizer{lbfgs}.name(), "lbfgs-ls");
}

}  // namespace
}  // namespace fnopt
