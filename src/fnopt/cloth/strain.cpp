#include <fnopt/cloth/strain.hpp>

#include <algorithm>

namespace fnopt {

double max_edge_strain(const Grid& grid, const VecX& x) {
  double longest = 0.0;
  for (int i = 0; i < grid.rows; ++i)
    for (int j = 0; j < grid.cols; ++j) {
      const int k = grid.index(i, j);
      if (j + 1 < grid.cols) longest = std::max(longest, (x.segment<3>(3 * k + 3) - x.segment<3>(3 * k)).norm());
      if (i + 1 < grid.rows)
        longest = std::max(longest, (x.segment<3>(3 * (k + grid.cols)) - x.segment<3>(3 * k)).norm());
    }
  return longest / grid.spacing - 1.0;
}

}  // namespace fnopt
