// The median shared by the per-step error's summary and the bench's repeated runs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fnopt/util/median.hpp>

namespace fnopt {
namespace {

TEST(Median, IsTheMiddleValueOrTheMeanOfTheTwoMiddleOnes) {
  EXPECT_EQ(median({3.0}), 3.0);
  EXPECT_EQ(median({5.0, 1.0, 3.0}), 3.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  // An outlier moves the mean, not the median.
  EXPECT_EQ(median({1.0, 2.0, 1e9}), 2.0);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(median({inf, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({inf, inf, 1.0}), inf);
  EXPECT_TRUE(std::isnan(median({})));
}

}  // namespace
}  // namespace fnopt
