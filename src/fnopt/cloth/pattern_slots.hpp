#pragma once
// The Hessian slots of a term's candidate stencils within a pattern that may hold more (self-repulsion,
// self-contact): the pattern changes, and with it the CHOLMOD analysis, only when a candidate is
// missing from it.
#include <algorithm>
#include <vector>

namespace fnopt {

// slots[c] = the index of candidates[c] in `pattern` (both sorted), where the pattern holds every
// candidate; false otherwise (the slots are then partial).
template <class Stencil>
bool pattern_slots(const std::vector<Stencil>& candidates, const std::vector<Stencil>& pattern, std::vector<int>& slots) {
  slots.resize(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const auto it = std::lower_bound(pattern.begin(), pattern.end(), candidates[c]);
    if (it == pattern.end() || !(*it == candidates[c])) return false;
    slots[c] = static_cast<int>(it - pattern.begin());
  }
  return true;
}

}  // namespace fnopt
