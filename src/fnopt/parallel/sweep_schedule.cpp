#include <fnopt/parallel/sweep_schedule.hpp>

#include <algorithm>
#include <numeric>

#include <fnopt/util/error.hpp>

namespace fnopt {

std::vector<int> schedule_largest_first(const std::vector<double>& costs, int ranks) {
  require(ranks >= 1, "schedule", "needs at least one rank");
  std::vector<std::size_t> order(costs.size());
  std::iota(order.begin(), order.end(), 0);
  // Ties keep the given order, so every rank sorts alike.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(ranks, 0.0);
  std::vector<int> rank_of(costs.size(), 0);
  for (std::size_t task : order) {
    const int least = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    rank_of[task] = least;
    load[least] += costs[task];
  }
  return rank_of;
}

}  // namespace fnopt
