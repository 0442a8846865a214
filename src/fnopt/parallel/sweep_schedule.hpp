#pragma once
// Which rank runs which task of a sweep (studies/sweep/sweep_runner.hpp): the independent tasks are
// handed out largest first, each to the rank with the least estimated work so far (the LPT rule
// of Graham 1969, within 4/3 of the best split when the estimates are right). Every rank
// computes the same split from the same estimates, so it needs no messages; a rank runs its
// tasks in their given order.
#include <cstddef>
#include <vector>

namespace fnopt {

// The rank of each task, for `ranks` ranks and the tasks' estimated costs.
std::vector<int> schedule_largest_first(const std::vector<double>& costs, int ranks);

}  // namespace fnopt
