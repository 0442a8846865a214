// The largest-first schedule of a sweep's tasks: every task gets one rank, ties keep the given
// order, and the busiest rank carries at most 4/3 of the best split's load (Graham's bound for
// LPT), checked against an exhaustive search on small random sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <fnopt/parallel/sweep_schedule.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double busiest(const std::vector<double>& costs, const std::vector<int>& rank_of, int ranks) {
  std::vector<double> load(ranks, 0.0);
  for (std::size_t t = 0; t < costs.size(); ++t) load[rank_of[t]] += costs[t];
  return *std::max_element(load.begin(), load.end());
}

// The smallest busiest-rank load over every assignment (ranks^tasks of them).
double best_busiest(const std::vector<double>& costs, int ranks) {
  std::vector<int> rank_of(costs.size(), 0);
  double best = INFINITY;
  while (true) {
    best = std::min(best, busiest(costs, rank_of, ranks));
    std::size_t t = 0;
    while (t < rank_of.size() && ++rank_of[t] == ranks) rank_of[t++] = 0;
    if (t == rank_of.size()) return best;
  }
}

TEST(SweepSchedule, OneRankRunsEverything) {
  EXPECT_EQ(schedule_largest_first({3.0, 1.0, 2.0}, 1), (std::vector<int>{0, 0, 0}));
  EXPECT_TRUE(schedule_largest_first({}, 4).empty());
}

TEST(SweepSchedule, LargestFirstToTheLeastLoadedRank) {
  // 10 -> rank 0; 7 -> rank 1; 5 -> rank 1 (7 < 10); 4 -> rank 0 (10 < 12); 1 -> rank 1 (12 < 14).
  EXPECT_EQ(schedule_largest_first({5.0, 10.0, 1.0, 7.0, 4.0}, 2), (std::vector<int>{1, 0, 1, 1, 0}));
  // Equal costs: handed out in the given order, round robin.
  EXPECT_EQ(schedule_largest_first({1.0, 1.0, 1.0, 1.0}, 3), (std::vector<int>{0, 1, 2, 0}));
}

TEST(SweepSchedule, WithinGrahamsBoundOfTheBestSplit) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int ranks = 2 + trial % 2;
    std::vector<double> costs(3 + trial % 6);
    for (double& c : costs) c = std::uniform_real_distribution<double>(0.1, 10.0)(rng);
    const std::vector<int> rank_of = schedule_largest_first(costs, ranks);
    for (int r : rank_of) ASSERT_TRUE(r >= 0 && r < ranks);
    const double best = best_busiest(costs, ranks);
    EXPECT_LE(busiest(costs, rank_of, ranks), (4.0 / 3.0 - 1.0 / (3.0 * ranks)) * best + 1e-12) << trial;
  }
}

TEST(SweepSchedule, RejectsNoRanks) { EXPECT_THROW(schedule_largest_first({1.0}, 0), Error); }

}  // namespace
}  // namespace fnopt
