#pragma once
// The test step of the proposal rule's and the training losses' tests: one time step of a 12 x 12
// cloth falling from rest with its two top corners held, at a = 0 with L and its masked gradient
// there. Includes fnopt/learned: for LibTorch-linked test folders only.
#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

struct FallingClothStep {
  Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective{grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81)};
  DirichletSet handles{grid.vertex_count(), {0, 11}};
  StepProblem problem{objective, handles};
  VecX a = VecX::Zero(grid.dof_count()), gradient;
  double value;

  FallingClothStep() {
    objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
    value = problem.value_gradient(a, gradient);
  }
  double grid_unit() const { return acceleration_per_grid_unit(grid, objective.dt()); }
  // The exact step length along -g at a for a quadratic L, g.g / g.Hg (Hg by a difference of
  // gradients).
  double gradient_step_length() {
    VecX shifted_gradient;
    const double eps = 1e-6 / gradient.norm();
    problem.value_gradient(a - eps * gradient, shifted_gradient);
    return gradient.squaredNorm() * eps / gradient.dot(gradient - shifted_gradient);
  }
  // A proposal of -t g (acceleration units), in grid units as the learned optimizer's samples.
  LearnedStep scaled_gradient(double t) const {
    return {to_coordinate_samples(gradient, grid, -t / grid_unit()), torch::full({3, 1, 1, 1}, 0.5)};
  }
};

}  // namespace fnopt
