#pragma once
// The projected step Hessian of an n x n cloth swinging sideways, its two top corners held
// (3 dofs per vertex): a cloth matrix large enough at n = 40 (4800 rows) for a supernodal factor
// of many supernodes of every width.
#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>

namespace fnopt::testing {

inline Eigen::SparseMatrix<double> swinging_cloth_hessian(int n = 40) {
  const Grid grid = Grid::make(n, n, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  VecX v = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k] = 1.5 * (k % grid.cols) / grid.cols;
  objective.begin_step(grid.rest_positions(), v);
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  return objective.hessian(VecX::Zero(grid.dof_count()), handles.free_index(), true);
}

}  // namespace fnopt::testing
