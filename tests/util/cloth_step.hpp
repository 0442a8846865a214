#pragma once
// A cloth time step for the optimizers' tests: a 12x12 cloth already swinging sideways, its two
// top corners held and moving.
#include <vector>

#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

struct ClothStep {
  Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective{grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81)};
  DirichletSet handles{grid.vertex_count(), {grid.index(0, 0), grid.index(0, grid.cols - 1)}};
  StepProblem problem{objective, handles};
  VecX x, v, a;

  ClothStep() {
    x = grid.rest_positions();
    v = VecX::Zero(grid.dof_count());
    for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k] = 1.5 * (k % grid.cols) / grid.cols;
    objective.begin_step(x, v);
    a = VecX::Zero(grid.dof_count());
    std::vector<Vec3> targets = {x.segment<3>(0) + Vec3(0.02, 0.01, 0.0),
                                 x.segment<3>(3 * (grid.cols - 1)) + Vec3(0.02, 0.01, 0.0)};
    handles.prescribe(a, x, v, targets, objective.dt());
  }
};

}  // namespace fnopt
