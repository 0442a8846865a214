// The compass search in a box: a quadratic's minimum inside the box and on its boundary, its
// evaluation budget, a point polled twice evaluated once, non-finite values, bad bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include <fnopt/fits/compass_search.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double shifted_quadratic(const VecX& x) { return (x - (VecX(3) << 0.3, -0.7, 0.05).finished()).squaredNorm(); }

TEST(CompassSearch, FindsAQuadraticsMinimumToTheFinalStep) {
  CompassSearchParams params{0.5, 1e-3, 1000};
  const CompassSearchResult r =
      minimize_by_compass(shifted_quadratic, VecX::Zero(3), VecX::Constant(3, -1.0), VecX::Constant(3, 1.0), params);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.final_step, params.final_step);
  EXPECT_NEAR(r.x[0], 0.3, 2e-3);
  EXPECT_NEAR(r.x[1], -0.7, 2e-3);
  EXPECT_NEAR(r.x[2], 0.05, 2e-3);
  EXPECT_DOUBLE_EQ(r.value, shifted_quadratic(r.x));
}

TEST(CompassSearch, StopsAtTheBoundAndAtTheBudget) {
  // The box x1 >= -0.25 holds the minimum's second coordinate at the bound.
  CompassSearchParams params{0.5, 1e-3, 1000};
  const CompassSearchResult bound =
      minimize_by_compass(shifted_quadratic, VecX::Zero(3), VecX::Constant(3, -0.25), VecX::Constant(3, 1.0), params);
  EXPECT_EQ(bound.x[1], -0.25);
  EXPECT_NEAR(bound.x[0], 0.3, 2e-3);

  params.max_evaluations = 7;
  int calls = 0;
  const CompassSearchResult budget = minimize_by_compass(
      [&](const VecX& x) {
        ++calls;
        return shifted_quadratic(x);
      },
      VecX::Zero(3), VecX::Constant(3, -1.0), VecX::Constant(3, 1.0), params);
  EXPECT_EQ(calls, 7);
  EXPECT_EQ(budget.evaluations, 7);
  EXPECT_FALSE(budget.converged);
  EXPECT_LT(budget.value, shifted_quadratic(VecX::Zero(3)));
}

TEST(CompassSearch, EvaluatesEachPointOnceAndNeverMovesToANonFiniteValue) {
  std::set<std::pair<long long, long long>> seen;
  int repeats = 0;
  const auto f = [&](const VecX& x) {
    repeats += !seen.insert({std::llround(x[0] * 1e6), std::llround(x[1] * 1e6)}).second;
    return x[0] > 0.2 ? std::nan("") : (x - VecX::Constant(2, 0.5)).squaredNorm();
  };
  const CompassSearchResult r =
      minimize_by_compass(f, VecX::Zero(2), VecX::Constant(2, -1.0), VecX::Constant(2, 1.0), {0.5, 1e-2, 500});
  EXPECT_EQ(repeats, 0);
  EXPECT_LE(r.x[0], 0.2);
  EXPECT_TRUE(std::isfinite(r.value));
  EXPECT_NEAR(r.x[1], 0.5, 1e-2);
}

TEST(CompassSearch, RefusesBadBoundsAndParameters) {
  EXPECT_THROW(minimize_by_compass(shifted_quadratic, VecX::Zero(3), VecX::Zero(2), VecX::Ones(3)), Error);
  EXPECT_THROW(minimize_by_compass(shifted_quadratic, VecX::Zero(3), VecX::Ones(3), VecX::Zero(3)), Error);
  EXPECT_THROW(minimize_by_compass(shifted_quadratic, VecX::Zero(3), -VecX::Ones(3), VecX::Ones(3), {0.0, 1e-3, 10}),
               Error);
  EXPECT_THROW(minimize_by_compass(shifted_quadratic, VecX::Zero(3), -VecX::Ones(3), VecX::Ones(3), {1.0, 1e-3, 0}),
               Error);
}

}  // namespace
}  // namespace fnopt
