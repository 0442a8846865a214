#include <fnopt/cloth/grid.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

Grid Grid::make(int rows, int cols, double size) {
  require(rows >= 3, "rows", "the grid needs at least 3 rows, got " + std::to_string(rows));
  require(cols >= 3, "cols", "the grid needs at least 3 columns, got " + std::to_string(cols));
  require(std::isfinite(size) && size > 0.0, "size", "must be a positive length in metres");
  return Grid{rows, cols, size / (std::max(rows, cols) - 1)};
}

VecX Grid::rest_positions() const {
  VecX x(dof_count());
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) vertex(x, index(i, j)) = Vec3(j * spacing, 0.0, -i * spacing);
  return x;
}

Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> Grid::triangles() const {
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces(2 * (rows - 1) * (cols - 1), 3);
  int f = 0;
  for (int i = 0; i + 1 < rows; ++i)
    for (int j = 0; j + 1 < cols; ++j) {
      const int a = index(i, j), b = a + 1, d = a + cols, e = d + 1;
      faces.row(f++) << a, b, e;
      faces.row(f++) << a, e, d;
    }
  return faces;
}

}  // namespace fnopt
