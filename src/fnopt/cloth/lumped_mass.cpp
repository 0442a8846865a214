#include <fnopt/cloth/lumped_mass.hpp>

namespace fnopt {

VecX lumped_masses(const Grid& grid, double density) {
  const double cell_mass = density * grid.spacing * grid.spacing;
  VecX m(grid.vertex_count());
  for (int i = 0; i < grid.rows; ++i)
    for (int j = 0; j < grid.cols; ++j) {
      const int cells_i = (i > 0) + (i + 1 < grid.rows);
      const int cells_j = (j > 0) + (j + 1 < grid.cols);
      m[grid.index(i, j)] = cell_mass * cells_i * cells_j / 4.0;
    }
  return m;
}

}  // namespace fnopt
