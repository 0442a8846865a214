#pragma once
// A regular cloth grid of rows x cols vertices with square cells. Rest pose (ARCSim layout,
// ../shared/data/arcsim/README.md): vertex (i, j) at (j*h, 0, -i*h), in the x-z plane, z up,
// row 0 at the top. h = size / (max(rows, cols) - 1), so non-square grids keep square cells.
#include <Eigen/Core>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct Grid {
  int rows = 0;
  int cols = 0;
  double spacing = 0.0;  // h, metres

  // Throws Error naming the field when rows or cols < 3 or size is not positive and finite.
  static Grid make(int rows, int cols, double size);

  int vertex_count() const { return rows * cols; }
  int dof_count() const { return 3 * rows * cols; }
  int index(int i, int j) const { return i * cols + j; }

  VecX rest_positions() const;
  // Triangles of each quad split along (i,j)-(i+1,j+1): (a, b, e) and (a, e, d) with
  // a = (i,j), b = (i,j+1), d = (i+1,j), e = (i+1,j+1): 2(R-1)(C-1) rows.
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles() const;
};

}  // namespace fnopt
