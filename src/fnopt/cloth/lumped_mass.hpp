#pragma once
#include <fnopt/cloth/grid.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

// Lumped vertex masses m_i = density * A_i with A_i = h^2 inside, h^2/2 on edges, h^2/4 at
// corners (each vertex owns a quarter of each adjacent cell): they sum to density * area.
VecX lumped_masses(const Grid& grid, double density);

}  // namespace fnopt
