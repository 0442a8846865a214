// The Newton reference: quadratic convergence on a stiff step, the tolerance it promises, that
// it never moves handles, and its fallbacks where the Hessian is indefinite (the shift on a
// buckling saddle, the stall guard where the shift crawls).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "baselines/newton.hpp"
#include "cloth/backward_euler.hpp"
#include "optimizer/inner_optimizer.hpp"
#include "simulation/rollout.hpp"

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
  StepProblem problem(objective, handles);
  NewtonParams exact;
  exact.max_cg_iterations = 0;  // a fresh factorization per iteration: plain Newton
  NewtonOptimizer newton(exact);
  const InnerSolveResult result =
      solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
  ASSERT_EQ(result.status, SolveStatus::Converged);
  EXPECT_LE(result.gradient_norm, 1e-9 * result.initial_gradient_norm);
  const auto& r = result.gradient_norms;
  std::printf("Newton ||g_k||/||g_0||:");
  for (double n : r) std::printf(" %.2e", n / r.front());
  std::printf("\nquadratic ratios ||g_k+1||/||g_k||^2 (scaled by ||g_0||):");
  for (std::size_t k = 1; k + 1 < r.size(); ++k) std::printf(" %.2e", r[k + 1] * r.front() / (r[k] * r[k]));
  std::printf("\n(%d of %d iterations used the projected Hessian)\n", static_cast<int>(newton.counters().projected_iterations),
              result.iterations);
  // Newton's local convergence: once ||g|| < 1e-2 ||g_0||, every step gains at least three
  // orders of magnitude (measured: 9.4e-3 -> 4.1e-6 -> 6.5e-10), and the exact Hessian is used
  // throughout (it stays positive definite on this step).
  EXPECT_EQ(static_cast<int>(newton.counters().projected_iterations), 0);
  std::size_t k = 0;
  while (r[k] > 1e-2 * r.front()) ++k;
  EXPECT_LE(r.size() - 1 - k, 3u);
  for (; k + 1 < r.size(); ++k) EXPECT_LT(r[k + 1], 1e-3 * r[k]);
}

// CG preconditioned by pqn's fixed matrix reaches the same converged step as plain Newton (it is
// slower: see NewtonParams::pqn_preconditioner), with no factorization on a step whose Hessian
// stays definite.
TEST(NewtonSolver, ThePqnPreconditionerGivesTheSameConvergedStep) {
  const Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  StepProblem problem(objective, handles);
  NewtonParams exact, pqn;
  exact.max_cg_iterations = 0;
  pqn.pqn_preconditioner = true;
  NewtonOptimizer direct(exact), preconditioned(pqn);
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count());
  for (int step = 0; step < 10; ++step) {  // the cloth falls from rest
    objective.begin_step(x, v);
    VecX a_direct = VecX::Zero(grid.dof_count()), a_pqn = a_direct;
    const auto options = NewtonOptimizer::reference_solve_options();
    ASSERT_EQ(solve_step(direct, problem, a_direct, options).status, SolveStatus::Converged);
    ASSERT_EQ(solve_step(preconditioned, problem, a_pqn, options).status, SolveStatus::Converged);
    EXPECT_LT((a_pqn - a_direct).norm(), 1e-7 * a_direct.norm()) << "step " << step;
    v += objective.dt() * a_direct;
    x += objective.dt() * v;
  }
  EXPECT_EQ(preconditioned.counters().factorizations, 0);
  EXPECT_GT(preconditioned.counters().cg_iterations, 0);
}

TEST(NewtonSolver, ReusedFactorsGiveTheSameStepWithFewerFactorizations) {
  const Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  StepProblem problem(objective, handles);
  NewtonParams exact;
  exact.max_cg_iterations = 0;
  NewtonOptimizer direct(exact), preconditioned;
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count());
  int iterations = 0;
  for (int step = 0; step < 20; ++step) {  // the cloth falls from rest for 20 steps
    objective.begin_step(x, v);
    VecX a_direct = VecX::Zero(grid.dof_count()), a_cg = a_direct;
    const auto options = NewtonOptimizer::reference_solve_options();
    ASSERT_EQ(solve_step(direct, problem, a_direct, options).status, SolveStatus::Converged);
    const InnerSolveResult cg = solve_step(preconditioned, problem, a_cg, options);
    ASSERT_EQ(cg.status, SolveStatus::Converged);
    iterations += cg.iterations;
    EXPECT_LT((a_cg - a_direct).norm(), 1e-7 * a_direct.norm()) << "step " << step;
    v += objective.dt() * a_direct;
    x += objective.dt() * v;
  }
  EXPECT_LT(preconditioned.counters().factorizations, iterations / 2);
  EXPECT_GT(preconditioned.counters().cg_iterations, 0);
}

TEST(NewtonSolver, LeavesHandleAccelerationsUntouched) {
  const Grid grid = Grid::make(8, 8, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, 7});
  VecX a = VecX::Zero(grid.dof_count());
  a.segment<3>(0) = Vec3(1, 2, 3);
  a.segment<3>(21) = Vec3(-4, 5, 0.5);
  const VecX before = a;
  StepProblem problem(objective, handles);
  NewtonOptimizer newton;
  ASSERT_EQ(solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options()).status,
            SolveStatus::Converged);
  EXPECT_EQ(a.segment<3>(0), before.segment<3>(0));
  EXPECT_EQ(a.segment<3>(21), before.segment<3>(21));
  EXPECT_GT((a - before).norm(), 0.0);
}

// A buckling step: the cloth starts compressed to 80 % along its rows with a small random
// out-of-plane wrinkle, so the exact Hessian is indefinite. The mass-shifted exact Hessian must
// take over, converge to the tolerance, and need fewer iterations than the per-stencil projected
// Hessian alone (max_shift = 0), which stalls near such saddles.
TEST(NewtonSolver, ShiftedHessianEscapesABucklingSaddle) {
  const Grid grid = Grid::make(14, 14, 1.0);
  Material material;  // the pre-fit default with 800 N/m stretch: undamped, soft shear
  material.stretch = 800.0;
  material.shear = 3.0;
  material.damping = 0.0;
  BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  VecX x = grid.rest_positions();
  std::srand(7);
  for (int k = 0; k < grid.vertex_count(); ++k) {
    x[3 * k] *= 0.8;
    x[3 * k + 1] = 1e-3 * (std::rand() / double(RAND_MAX) - 0.5);
  }
  int iterations[2] = {0, 0};
  long shifted = 0;
  for (int variant = 0; variant < 2; ++variant) {
    NewtonParams params;
    if (variant == 1) params.max_shift = 0.0;
    NewtonOptimizer newton(params);
    objective.begin_step(x, VecX::Zero(grid.dof_count()));
    StepProblem problem(objective, handles);
    VecX a = VecX::Zero(grid.dof_count());
    const InnerSolveResult result = solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
    if (variant == 0) {
      EXPECT_TRUE(is_converged(result.status)) << to_string(result.status);
      shifted = newton.counters().shifted_iterations;
    }
    iterations[variant] = result.iterations;
  }
  std::printf("buckling step: %d iterations with the shift (%ld shifted), %d with the projected Hessian only\n",
              iterations[0], shifted, iterations[1]);
  EXPECT_GT(shifted, 0);
  EXPECT_LT(iterations[0], iterations[1]);
}

// Solves every step with `main`; on step `twin_step` (counted from 0) it first solves the same
// step, from the same start, with `twin` and keeps that result. So two solvers are compared on
// one state that takes a long rollout to reach, without running the rollout twice.
class TwinOnOneStep : public InnerOptimizer {
 public:
  TwinOnOneStep(InnerOptimizer& main, InnerOptimizer& twin, int twin_step, InnerSolveOptions options)
      : main_(main), twin_(twin), twin_step_(twin_step), options_(options) {}
  std::string name() const override { return main_.name(); }
  std::string settings() const override { return main_.settings(); }
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override {
    if (step_++ == twin_step_) {
      VecX twin_a = a;
      twin_result_ = solve_step(twin_, problem, twin_a, options_);
    }
    main_.begin_step(problem, a, value, gradient);
  }
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    return main_.iterate(problem, a, value, gradient);
  }
  const InnerSolveResult& twin_result() const { return twin_result_; }

 private:
  InnerOptimizer& main_;
  InnerOptimizer& twin_;
  int step_ = 0;
  const int twin_step_;
  const InnerSolveOptions options_;
  InnerSolveResult twin_result_;
};

// A real stall: the 64^2 benchmark scene, motion xz_v2, whose step 114 needs the shift mu = 210
// (the exact Hessian stays indefinite up to mu ~ 105 along the whole solve). The shift alone
// then gains ~0.5 % of ||g|| per iteration and ends the step at its budget; the stall guard
// switches to the projected Hessian for an iteration and the step converges. Steps 1-113 take
// 4-9 iterations either way; they run once (about 20 s), and step 114 is solved from the same
// state with and without the guard.
TEST(NewtonSolver, StallGuardFinishesAStepWhereTheShiftCrawls) {
  Scene scene;
  scene.rows = scene.cols = 64;
  scene.motion = "xz_v2";
  scene.frames = 114;
  RolloutOptions options;
  options.solve = {150, 1e-9};
  NewtonOptimizer guarded;
  NewtonParams unguarded_params;
  unguarded_params.max_slow_shifted_iterations = 0;
  NewtonOptimizer unguarded(unguarded_params);
  TwinOnOneStep solvers(guarded, unguarded, 113, options.solve);
  const RolloutResult r = run_rollout(resolve(scene), solvers, options);
  ASSERT_FALSE(r.diverged) << r.divergence;
  ASSERT_EQ(r.steps.size(), 114u);
  const int unconverged = static_cast<int>(r.steps.size()) - r.converged_steps();
  int max_iterations = 0;
  for (const auto& s : r.steps) max_iterations = std::max(max_iterations, s.iterations);
  const InnerSolveResult& off = solvers.twin_result();
  std::printf("guard on: %d unconverged steps, at most %d iterations, %ld stall switches, step 114 in %d iterations\n"
              "guard off: step 114 %s after %d iterations, ||g|| = %.2e ||g0||\n",
              unconverged, max_iterations, guarded.counters().stalled_shifts, r.steps.back().iterations,
              to_string(off.status), off.iterations, off.gradient_norm / off.initial_gradient_norm);
  EXPECT_EQ(unconverged, 0);
  EXPECT_GT(guarded.counters().stalled_shifts, 0);
  EXPECT_EQ(off.status, SolveStatus::IterationBudget);
  EXPECT_EQ(unguarded.counters().stalled_shifts, 0);
}

// settings() keys compare's reference cache: changing any parameter must change it.
TEST(NewtonParams, EveryParameterChangesTheSettingsString) {
  const std::string base = NewtonOptimizer{}.settings();
  const std::vector<void (*)(NewtonParams&)> changes = {
      [](NewtonParams& p) { p.armijo = 2e-4; },           [](NewtonParams& p) { p.backtrack = 0.6; },
      [](NewtonParams& p) { p.max_backtracks = 30; },     [](NewtonParams& p) { p.forcing_cap = 2e-2; },
      [](NewtonParams& p) { p.max_cg_iterations = 10; },  [](NewtonParams& p) { p.max_shift = 1e5; },
      [](NewtonParams& p) { p.shift_growth = 3.0; },      [](NewtonParams& p) { p.max_slow_shifted_iterations = 20; },
      [](NewtonParams& p) { p.slow_shift_progress = 0.8; }, [](NewtonParams& p) { p.pqn_preconditioner = true; }};
  for (std::size_t i = 0; i < changes.size(); ++i) {
    NewtonParams params;
    changes[i](params);
    EXPECT_NE(NewtonOptimizer(params).settings(), base) << "change " << i;
  }
}

TEST(NewtonParams, RejectsInvalidValues) {
  NewtonParams p;
  p.armijo = 0.0;
  EXPECT_ANY_THROW(p.validate());
  p = NewtonParams{};
  p.backtrack = 1.5;
  EXPECT_ANY_THROW(NewtonOptimizer{p});
  p = NewtonParams{};
  p.shift_growth = 1.0;
  EXPECT_ANY_THROW(p.validate());
  p = NewtonParams{};
  p.max_slow_shifted_iterations = -1;
  EXPECT_ANY_THROW(p.validate());
  p = NewtonParams{};
  p.slow_shift_progress = 1.0;
  EXPECT_ANY_THROW(p.validate());
}

}  // namespace
}  // namespace fnopt
