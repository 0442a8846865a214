// Projected L-BFGS in a box: the minimum inside the box, a minimum on its boundary, and the
// statuses and errors it reports.
#include <gtest/gtest.h>

#include <fnopt/fits/bounded_lbfgs.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// Rosenbrock's function, minimum 0 at (1, 1).
double rosenbrock(const VecX& x, VecX& g) {
  const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
  g.resize(2);
  g[0] = -2.0 * a - 400.0 * x[0] * b;
  g[1] = 200.0 * b;
  return a * a + 100.0 * b * b;
}

TEST(BoundedLbfgs, FindsTheMinimumInsideTheBox) {
  BoundedLbfgsParams params;
  params.max_iterations = 200;
  const BoundedLbfgsResult r =
      minimize_in_box(rosenbrock, VecX::Constant(2, -1.0), VecX::Constant(2, -2.0), VecX::Constant(2, 2.0), params);
  EXPECT_EQ(r.status, BoundedLbfgsStatus::Converged) << to_string(r.status);
  EXPECT_NEAR(r.x[0], 1.0, 1e-6);
  EXPECT_NEAR(r.x[1], 1.0, 1e-6);
}

TEST(BoundedLbfgs, StopsOnTheBoundWhereTheGradientPointsOut) {
  // The box x1 <= 0.5 cuts the valley: the constrained minimum has x1 = 0.5 and, along it,
  // x0 minimising (1 - x0)^2 + 100 (0.5 - x0^2)^2, where the derivative in x0 vanishes.
  BoundedLbfgsParams params;
  params.max_iterations = 200;
  const BoundedLbfgsResult r =
      minimize_in_box(rosenbrock, VecX::Zero(2), VecX::Constant(2, -2.0), (VecX(2) << 2.0, 0.5).finished(), params);
  EXPECT_EQ(r.status, BoundedLbfgsStatus::Converged) << to_string(r.status);
  EXPECT_EQ(r.x[1], 0.5);
  VecX g;
  rosenbrock(r.x, g);
  EXPECT_LT(g[1], 0.0);  // it pushes against the bound
  EXPECT_NEAR(g[0], 0.0, 1e-6);
}

TEST(BoundedLbfgs, KeepsToItsEvaluationBudget) {
  BoundedLbfgsParams params;
  params.max_iterations = 200;
  params.max_evaluations = 9;
  int calls = 0;
  const BoundedLbfgsResult r = minimize_in_box(
      [&](const VecX& x, VecX& g) {
        ++calls;
        return rosenbrock(x, g);
      },
      VecX::Constant(2, -1.0), VecX::Constant(2, -2.0), VecX::Constant(2, 2.0), params);
  EXPECT_EQ(r.status, BoundedLbfgsStatus::EvaluationBudget) << to_string(r.status);
  EXPECT_EQ(calls, 9);
  EXPECT_EQ(r.evaluations, 9);
  VecX g;
  EXPECT_LT(r.value, rosenbrock(VecX::Constant(2, -1.0), g));
  EXPECT_EQ(r.value, rosenbrock(r.x, g));
}

TEST(BoundedLbfgs, StopsWhereAStepGainsTooLittle) {
  BoundedLbfgsParams full, stalling;
  full.max_iterations = stalling.max_iterations = 200;
  stalling.relative_decrease = 0.05;
  const VecX start = VecX::Constant(2, -1.0), lower = VecX::Constant(2, -2.0), upper = VecX::Constant(2, 2.0);
  const BoundedLbfgsResult converged = minimize_in_box(rosenbrock, start, lower, upper, full);
  const BoundedLbfgsResult stalled = minimize_in_box(rosenbrock, start, lower, upper, stalling);
  EXPECT_EQ(stalled.status, BoundedLbfgsStatus::Converged) << to_string(stalled.status);
  EXPECT_LT(stalled.iterations, converged.iterations);
  EXPECT_GT(stalled.value, converged.value);
  stalling.relative_decrease = -1.0;
  EXPECT_THROW(minimize_in_box(rosenbrock, start, lower, upper, stalling), Error);
}

TEST(BoundedLbfgs, ReportsANonFiniteStartAndRefusesBadBounds) {
  const auto nan = [](const VecX& x, VecX& g) {
    g = VecX::Zero(x.size());
    return std::nan("");
  };
  EXPECT_EQ(minimize_in_box(nan, VecX::Zero(2), VecX::Constant(2, -1.0), VecX::Constant(2, 1.0)).status,
            BoundedLbfgsStatus::NonFinite);
  EXPECT_THROW(minimize_in_box(rosenbrock, VecX::Zero(2), VecX::Constant(2, 1.0), VecX::Constant(2, -1.0)), Error);
  EXPECT_THROW(minimize_in_box(rosenbrock, VecX::Zero(2), VecX::Constant(3, -1.0), VecX::Constant(2, 1.0)), Error);
}

}  // namespace
}  // namespace fnopt
