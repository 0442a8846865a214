#pragma once
#include <fnopt/cloth/grid.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

// max over grid edges of |e|/h - 1: 0 at rest, 0.1 for 10 % stretch.
double max_edge_strain(const Grid& grid, const VecX& x);

}  // namespace fnopt
