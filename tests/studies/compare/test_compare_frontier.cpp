// The error-time frontier of compare (studies/compare/compare_frontier.hpp): which runs are Pareto-optimal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <fnopt/studies/compare/compare_frontier.hpp>

namespace fnopt {
namespace {

using Point = std::pair<double, double>;  // (ms/frame, e_CD)

bool dominates(const Point& a, const Point& b) {
  return a.first <= b.first && a.second <= b.second && (a.first < b.first || a.second < b.second);
}

TEST(ParetoOptimal, KeepsTheRunsNothingIsBothFasterAndCloserThan) {
  const std::vector<Point> points = {{1, 5}, {2, 3}, {3, 3}, {4, 1}, {2, 6}, {NAN, 0}, {5, 1}, {0.5, INFINITY}};
  const std::vector<bool> expected = {true, true, false, true, false, false, false, false};
  EXPECT_EQ(pareto_optimal(points), expected);
}

TEST(ParetoOptimal, EqualRunsAreBothOnTheFrontier) {
  EXPECT_EQ(pareto_optimal({{2, 3}, {2, 3}, {3, 4}}), (std::vector<bool>{true, true, false}));
}

TEST(ParetoOptimal, IsAStaircaseThatDominatesEveryOtherFinishedRun) {
  std::mt19937 random(7);
  std::lognormal_distribution<double> ms(3.0, 1.0), error(0.0, 1.5);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Point> points(40);
    for (auto& p : points) p = {ms(random), error(random)};
    points[trial % 40].second = NAN;  // a diverged run
    const std::vector<bool> optimal = pareto_optimal(points);
    std::vector<Point> front;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (optimal[i]) front.push_back(points[i]);
    ASSERT_FALSE(front.empty());
    std::sort(front.begin(), front.end());
    for (std::size_t k = 1; k < front.size(); ++k) EXPECT_LT(front[k].second, front[k - 1].second);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (optimal[i] || !std::isfinite(points[i].second)) continue;
      EXPECT_TRUE(std::any_of(front.begin(), front.end(), [&](const Point& f) { return dominates(f, points[i]); }));
    }
  }
}

}  // namespace
}  // namespace fnopt
