// The Newton reference: quadratic convergence on a stiff step, the tolerance it promises, and
// that it never moves handles.
#include <gtest/gtest.h>

#include <cstdio>

#include "baselines/newton.hpp"
#include "cloth/backward_euler.hpp"

namespace fnopt {
namespace {

TEST(NewtonSolver, ConvergesQuadraticallyOnAStiffStep) {
  const Grid grid = Grid::make(16, 16, 1.0);
  Material stiff;
  stiff.stretch = 3000.0;  // 100x the default: k~_s ~ 6e3 at 16^2
  stiff.bend = 1e-3;
  BackwardEulerObjective objective(grid, stiff, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {grid.index(0, 0), grid.index(0, grid.cols - 1)});
  // A strongly deformed start: the cloth swinging sideways at 2 m/s.
  VecX v = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k] = 2.0 * (k % grid.cols) / grid.cols;
  objective.begin_step(grid.rest_positions(), v);
  VecX a = VecX::Zero(grid.dof_count());
  const NewtonResult result = NewtonSolver().solve(objective, handles, a);
  ASSERT_EQ(result.status, SolveStatus::Converged);
  EXPECT_LE(result.gradient_norm, 1e-9 * result.initial_gradient_norm);
  const auto& r = result.gradient_norms;
  std::printf("Newton ||g_k||/||g_0||:");
  for (double n : r) std::printf(" %.2e", n / r.front());
  std::printf("\nquadratic ratios ||g_k+1||/||g_k||^2 (scaled by ||g_0||):");
  for (std::size_t k = 1; k + 1 < r.size(); ++k) std::printf(" %.2e", r[k + 1] * r.front() / (r[k] * r[k]));
  std::printf("\n(%d of %d iterations used the projected Hessian)\n", result.projected_iterations,
              result.iterations);
  // Newton's local convergence: once ||g|| < 1e-2 ||g_0||, every step gains at least three
  // orders of magnitude (measured: 9.4e-3 -> 4.1e-6 -> 6.5e-10), and the exact Hessian is used
  // throughout (it stays positive definite on this step).
  EXPECT_EQ(result.projected_iterations, 0);
  std::size_t k = 0;
  while (r[k] > 1e-2 * r.front()) ++k;
  EXPECT_LE(r.size() - 1 - k, 3u);
  for (; k + 1 < r.size(); ++k) EXPECT_LT(r[k + 1], 1e-3 * r[k]);
}

TEST(NewtonSolver, LeavesHandleAccelerationsUntouched) {
  const Grid grid = Grid::make(8, 8, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, 7});
  VecX a = VecX::Zero(grid.dof_count());
  a.segment<3>(0) = Vec3(1, 2, 3);
  a.segment<3>(21) = Vec3(-4, 5, 0.5);
  const VecX before = a;
  ASSERT_EQ(NewtonSolver().solve(objective, handles, a).status, SolveStatus::Converged);
  EXPECT_EQ(a.segment<3>(0), before.segment<3>(0));
  EXPECT_EQ(a.segment<3>(21), before.segment<3>(21));
  EXPECT_GT((a - before).norm(), 0.0);
}

TEST(NewtonParams, RejectsInvalidValues) {
  NewtonParams p;
  p.relative_tolerance = 0.0;
  EXPECT_ANY_THROW(p.validate());
  p = NewtonParams{};
  p.backtrack = 1.5;
  EXPECT_ANY_THROW(NewtonSolver{p});
}

}  // namespace
}  // namespace fnopt
