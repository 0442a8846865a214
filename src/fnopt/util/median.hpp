#pragma once
// The median of a list of numbers: the middle one after sorting, or the mean of the two middle ones for an even
// count; NaN for an empty list. Infinities sort to the ends like any value.
#include <algorithm>
#include <cmath>
#include <vector>

namespace fnopt {

inline double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t half = values.size() / 2;
  return values.size() % 2 ? values[half] : 0.5 * (values[half - 1] + values[half]);
}

}  // namespace fnopt
