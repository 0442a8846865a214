// Levenberg-Marquardt on a Gauss-Newton model in a box: Rosenbrock as least squares converges to
// its minimum, a minimum outside the box ends at the bound, and each stop says why.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fnopt/fits/bounded_gauss_newton.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

// Rosenbrock as residuals r = (10 (y - x^2), 1 - x): f = |r|^2, g = 2 J^T r, G = 2 J^T J, shifted by
// `target` so that the minimum is at (1, 1) + target.
GaussNewtonObjective rosenbrock(const VecX& target = VecX::Zero(2)) {
  return [target](const VecX& p, VecX& g, Eigen::MatrixXd& G) {
    const double x = p[0] - target[0], y = p[1] - target[1];
    const Eigen::Vector2d r(10.0 * (y - x * x), 1.0 - x);
    Eigen::Matrix2d J;
    J << -20.0 * x, 10.0, -1.0, 0.0;
    g = 2.0 * J.transpose() * r;
    G = 2.0 * J.transpose() * J;
    return r.squaredNorm();
  };
}

const VecX kLower = VecX::Constant(2, -5.0), kUpper = VecX::Constant(2, 5.0);

// From the textbook start (-1.2, 1), along the curved valley: 32 evaluations.
TEST(BoundedGaussNewton, RosenbrockConvergesToItsMinimum) {
  BoundedGaussNewtonParams params;
  params.max_evaluations = 50;
  const BoundedGaussNewtonResult fit =
      minimize_by_gauss_newton(rosenbrock(), Eigen::Vector2d(-1.2, 1.0), kLower, kUpper, params);
  EXPECT_EQ(fit.status, BoundedGaussNewtonStatus::Stationary) << to_string(fit.status);
  EXPECT_NEAR(fit.x[0], 1.0, 1e-6);
  EXPECT_NEAR(fit.x[1], 1.0, 1e-6);
  EXPECT_LT(fit.value, 1e-12);
  EXPECT_LE(fit.evaluations, 40);
  EXPECT_GE(fit.iterations, 1);
}

// The minimum at (3, 1) with x <= 2: held at x = 2 and minimised in y there, y = x^2 shifted.
TEST(BoundedGaussNewton, AMinimumOutsideTheBoxEndsAtTheBound) {
  const VecX upper = Eigen::Vector2d(2.0, 5.0);
  const BoundedGaussNewtonResult fit =
      minimize_by_gauss_newton(rosenbrock(Eigen::Vector2d(2.0, 0.0)), Eigen::Vector2d(0.0, 0.0), kLower, upper);
  EXPECT_EQ(fit.status, BoundedGaussNewtonStatus::Stationary) << to_string(fit.status);
  EXPECT_EQ(fit.x[0], 2.0);
  EXPECT_NEAR(fit.x[1], 0.0, 1e-5);  // y - 0 = x'^2 with x' = 0
}

TEST(BoundedGaussNewton, EachStopSaysWhy) {
  BoundedGaussNewtonParams params;
  params.max_evaluations = 2;
  EXPECT_EQ(minimize_by_gauss_newton(rosenbrock(), Eigen::Vector2d(-1.2, 1.0), kLower, kUpper, params).status,
            BoundedGaussNewtonStatus::EvaluationBudget);
  // A gradient of the wrong sign: no step along the model lowers the loss.
  const GaussNewtonObjective wrong = [](const VecX& p, VecX& g, Eigen::MatrixXd& G) {
    g = -2.0 * p;
    G = 2.0 * Eigen::MatrixXd::Identity(p.size(), p.size());
    return p.squaredNorm();
  };
  params.max_evaluations = 200;
  const BoundedGaussNewtonResult stuck = minimize_by_gauss_newton(wrong, Eigen::Vector2d(1.0, 1.0), kLower, kUpper, params);
  EXPECT_EQ(stuck.status, BoundedGaussNewtonStatus::NoDecrease);
  EXPECT_EQ(stuck.x, Eigen::Vector2d(1.0, 1.0));
  const GaussNewtonObjective infinite = [](const VecX& p, VecX& g, Eigen::MatrixXd& G) {
    g = p;
    G = Eigen::MatrixXd::Identity(p.size(), p.size());
    return std::numeric_limits<double>::infinity();
  };
  EXPECT_EQ(minimize_by_gauss_newton(infinite, Eigen::Vector2d(1.0, 1.0), kLower, kUpper).status,
            BoundedGaussNewtonStatus::NonFinite);
}

// Residuals (x - 1, y - 2, 1): a floor of 1 that no x lowers, as a noise floor. With a decrease
// tolerance the search ends "settled" once the model promises less than that share of the loss
// (here after one step, at loss 1 + a hair); without one it goes on to the stationary point.
TEST(BoundedGaussNewton, SettlesWhereTheModelPromisesLittleOfTheLoss) {
  const GaussNewtonObjective floored = [](const VecX& p, VecX& g, Eigen::MatrixXd& G) {
    const Eigen::Vector3d r(p[0] - 1.0, p[1] - 2.0, 1.0);
    g = 2.0 * r.head<2>();
    G = 2.0 * Eigen::Matrix2d::Identity();
    return r.squaredNorm();
  };
  BoundedGaussNewtonParams params;
  params.decrease_tolerance = 0.1;
  const BoundedGaussNewtonResult settled =
      minimize_by_gauss_newton(floored, Eigen::Vector2d(0.0, 0.0), kLower, kUpper, params);
  EXPECT_EQ(settled.status, BoundedGaussNewtonStatus::Settled) << to_string(settled.status);
  EXPECT_EQ(settled.evaluations, 2);
  const double promised = (settled.x - Eigen::Vector2d(1.0, 2.0)).squaredNorm();  // -(g.s + s.G s/2), s the GN step
  EXPECT_LE(promised, 0.1 * settled.value);
  EXPECT_GT(promised, 0.0);
  params.decrease_tolerance = 0.0;
  const BoundedGaussNewtonResult stationary =
      minimize_by_gauss_newton(floored, Eigen::Vector2d(0.0, 0.0), kLower, kUpper, params);
  EXPECT_EQ(stationary.status, BoundedGaussNewtonStatus::Stationary) << to_string(stationary.status);
  EXPECT_GT(stationary.evaluations, settled.evaluations);
}

TEST(BoundedGaussNewton, ParamsAndBoundsAreValidated) {
  BoundedGaussNewtonParams params;
  params.max_evaluations = 0;
  EXPECT_TRUE(testing::throws_error([&] { params.validate(); }, "max_evaluations: "));
  params = {};
  params.step_tolerance = 0.0;
  EXPECT_TRUE(testing::throws_error([&] { params.validate(); }, "step_tolerance: "));
  for (double tolerance : {-0.1, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    params = {};
    params.decrease_tolerance = tolerance;
    EXPECT_TRUE(testing::throws_error([&] { params.validate(); }, "decrease_tolerance: ")) << tolerance;
  }
  params = {};
  params.max_damping = params.initial_damping;
  EXPECT_TRUE(testing::throws_error([&] { params.validate(); }, "max_damping: "));
  EXPECT_TRUE(testing::throws_error(
      [] { minimize_by_gauss_newton(rosenbrock(), Eigen::Vector2d(0.0, 0.0), kUpper, kLower); }, "bounds: "));
  EXPECT_TRUE(testing::throws_error(
      [] { minimize_by_gauss_newton(rosenbrock(), Eigen::Vector2d(0.0, 0.0), VecX::Zero(3), kUpper); }, "bounds: "));
}

}  // namespace
}  // namespace fnopt
