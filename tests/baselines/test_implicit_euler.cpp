// Linearly implicit Euler: without handles its one solve is Baraff & Witkin's
// (M + dt^2 K) dv = dt (f_t - dt K v_t), K the (projected) stiffness at x_t; with handles it
// never moves them; and it is one solve per step.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <fnopt/baselines/implicit_euler.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include "tests/util/cloth_step.hpp"

namespace fnopt {
namespace {

TEST(ImplicitEuler, IsBaraffAndWitkinsLinearisedStep) {
  const Grid grid = Grid::make(6, 5, 1.0);
  Material material;
  material.damping = 0.0;  // Baraff & Witkin's equation without damping forces
  BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet none(grid.vertex_count(), {});
  StepProblem problem(objective, none);
  // A swinging, sagging start.
  VecX x = grid.rest_positions(), v(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) {
    x[3 * k + 1] += 0.02 * std::sin(3.0 * k);
    v.segment<3>(3 * k) = Vec3(0.5, -0.2 * (k % 3), 0.3);
  }
  const double dt = objective.dt();
  // K and f at x_t, from the objective started at x_t at rest (x(a = 0) = x_t there).
  std::vector<int> all(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) all[k] = k;
  objective.begin_step(x, VecX::Zero(grid.dof_count()));
  const VecX zero = VecX::Zero(grid.dof_count());
  VecX gradient;
  objective.value_gradient(zero, gradient);                     // dt^2 (grad P(x_t) - M g)
  const Eigen::MatrixXd H(objective.hessian(zero, all, true));  // dt^2 M + dt^4 K
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(grid.dof_count(), grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) M.block<3, 3>(3 * k, 3 * k) = objective.masses()[k] * Mat3::Identity();
  const Eigen::MatrixXd K = (H - dt * dt * M) / (dt * dt * dt * dt);
  const VecX f = -gradient / (dt * dt);
  const VecX dv = (M + dt * dt * K).ldlt().solve(dt * (f - dt * K * v));

  objective.begin_step(x, v);
  VecX a = VecX::Zero(grid.dof_count());
  ImplicitEulerOptimizer euler;
  const InnerSolveResult r = solve_step(euler, problem, a, {1, 0.0});
  EXPECT_EQ(r.iterations, 1);
  EXPECT_LT((dt * a - dv).norm(), 1e-9 * dv.norm());
}

TEST(ImplicitEuler, NeverMovesAHandleAndSolvesOncePerStep) {
  ClothStep step;
  ImplicitEulerOptimizer euler;
  VecX a = step.a;
  const InnerSolveResult r = solve_step(euler, step.problem, a, {5, 0.0});
  for (int h : step.handles.fixed_vertices()) EXPECT_EQ(a.segment<3>(3 * h), step.a.segment<3>(3 * h)) << h;
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(r.status, SolveStatus::IterationBudget);
  EXPECT_LT(r.value, r.initial_value);
}

}  // namespace
}  // namespace fnopt
