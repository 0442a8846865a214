// Randomized smoothing against what it estimates: on a quadratic the smoothed gradient is the
// gradient (antithetic pairs cancel the odd terms exactly); on |x| the smoothed loss is the known
// Gaussian convolution, whose gradient at 0 is 0 where the exact one jumps; the draws are common
// to every point; bad settings are refused.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/fits/randomized_smoothing.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

TEST(RandomizedSmoothing, OnAQuadraticTheSmoothedGradientIsTheGradient) {
  const RandomizedSmoothing smoothing({0.3, 6, 7}, 3);
  const Eigen::Vector3d a(1.0, 2.0, 0.5);
  const auto f = [&](const VecX& x, VecX& g) {
    g = 2.0 * a.cwiseProduct(x);
    return x.dot(a.cwiseProduct(x));
  };
  const VecX x = Eigen::Vector3d(0.4, 0.1, -1.0);
  const SmoothedEvaluation s = smoothing.evaluate(f, x);
  VecX exact;
  const double value = f(x, exact);
  EXPECT_LT((s.gradient - exact).norm(), 1e-12);
  EXPECT_GT(s.value, value);  // plus the mean of e^T A e over the draws, positive for A > 0
  EXPECT_GT(s.standard_error, 0.0);   // each draw's gradient differs
}

// L = |x| in one dimension: at x = 0 the exact gradient is +-1 by side, the smoothed one 0 (the
// draws are symmetric), and away from 0 by many sigma it is sign(x). With many draws the smoothed
// value at 0 nears E|sigma e| = sigma sqrt(2 / pi).
TEST(RandomizedSmoothing, SmoothsAKink) {
  const double sigma = 0.1;
  const RandomizedSmoothing smoothing({sigma, 4000, 3}, 1);
  const auto f = [](const VecX& x, VecX& g) {
    g = VecX::Constant(1, x[0] >= 0.0 ? 1.0 : -1.0);
    return std::abs(x[0]);
  };
  const SmoothedEvaluation at_zero = smoothing.evaluate(f, VecX::Zero(1));
  EXPECT_NEAR(at_zero.gradient[0], 0.0, 1e-12);
  EXPECT_NEAR(at_zero.value, sigma * std::sqrt(2.0 / M_PI), 0.03 * sigma);
  EXPECT_NEAR(at_zero.standard_error, 1.0 / std::sqrt(4000.0), 1e-3);
  EXPECT_NEAR(smoothing.evaluate(f, VecX::Constant(1, 10 * sigma)).gradient[0], 1.0, 1e-9);
}

// Common random numbers: the same draws at every point, so the estimate is a deterministic function.
TEST(RandomizedSmoothing, TheDrawsAreTheSameAtEveryPoint) {
  const RandomizedSmoothing smoothing({0.2, 4, 11}, 2);
  std::vector<VecX> seen;
  const auto record = [&](const VecX& x, VecX& g) {
    seen.push_back(x);
    g = VecX::Zero(2);
    return 0.0;
  };
  smoothing.evaluate(record, VecX::Zero(2));
  smoothing.evaluate(record, VecX::Constant(2, 1.0));
  ASSERT_EQ(seen.size(), 8u);
  for (int k = 0; k < 4; ++k) EXPECT_LT((seen[4 + k] - VecX::Constant(2, 1.0) - seen[k]).norm(), 1e-15);
  EXPECT_LT((seen[0] + seen[1]).norm(), 1e-15);  // an antithetic pair
}

TEST(RandomizedSmoothing, BadSettingsAreRefused) {
  EXPECT_TRUE(testing::throws_error([] { SmoothingParams{-1.0, 4, 1}.validate(); }, "sigma: "));
  EXPECT_TRUE(testing::throws_error([] { SmoothingParams{0.1, 3, 1}.validate(); }, "samples: "));
  EXPECT_TRUE(testing::throws_error([] { SmoothingParams{0.1, 0, 1}.validate(); }, "samples: "));
  EXPECT_FALSE(SmoothingParams{}.enabled());
}

}  // namespace
}  // namespace fnopt
