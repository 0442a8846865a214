// The Newton reference: quadratic convergence on a stiff step, the residual-acceleration stop it
// promises, the same step with a factor kept across iterations and steps as with a fresh one, CG
// stopped on a stale factor with the same rollout, handles never moved, and a buckling step where the Hessian is
// indefinite (negative curvature followed to a minimum). The symmetric saddle is tested on the subproblem
// (test_steihaug_cg.cpp), and newton-min leaving it here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

// A fresh factor of P at every iteration: Newton's own convergence, without the preconditioner's age.
NewtonParams fresh_factor_every_iteration() {
  NewtonParams p;
  p.refactor_cg_iterations = 0;
  p.reuse_factor_across_steps = false;
  return p;
}

// Whether the exact Hessian at a is positive definite (its Cholesky succeeds).
bool hessian_is_definite(BackwardEulerObjective& objective, const DirichletSet& handles, const VecX& a) {
  SparseCholesky cholesky;
  return cholesky.factorize_matrix(objective.hessian(a, handles.free_index(), false));
}

// Newton iterations per step of two solvers run on the same 20 steps.
struct SideBySide {
  std::vector<int> reference, other;
};

// Solves 20 steps of an n x n cloth falling from rest, two corners held, with `reference` and
// `other` to a residual acceleration of 1e-7 m/s^2, the cloth advanced by the reference's steps.
// Every step must converge in both and end at the same acceleration (within 1e-6 of its norm: each
// solver stops at its own point inside the tolerance).
SideBySide solve_side_by_side(int n, NewtonOptimizer& reference, NewtonOptimizer& other) {
  const Grid grid = Grid::make(n, n, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  StepProblem problem(objective, handles);
  InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
  options.acceleration_tolerance = 1e-7;
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count());
  SideBySide iterations;
  for (int step = 0; step < 20; ++step) {
    objective.begin_step(x, v);
    VecX a_reference = VecX::Zero(grid.dof_count()), a_other = a_reference;
    const InnerSolveResult r = solve_step(reference, problem, a_reference, options);
    const InnerSolveResult o = solve_step(other, problem, a_other, options);
    EXPECT_EQ(r.status, SolveStatus::Converged) << "step " << step;
    EXPECT_EQ(o.status, SolveStatus::Converged) << "step " << step;
    EXPECT_LT((a_other - a_reference).norm(), 1e-6 * a_reference.norm()) << "step " << step;
    iterations.reference.push_back(r.iterations);
    iterations.other.push_back(o.iterations);
    v += objective.dt() * a_reference;
    x += objective.dt() * v;
  }
  return iterations;
}

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
  NewtonParams params = fresh_factor_every_iteration();
  params.acceleration_tolerance = 1e-7;  // far down, to see the quadratic tail (CG's floor follows)
  NewtonOptimizer newton(params);
  InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
  options.acceleration_tolerance = params.acceleration_tolerance;
  const InnerSolveResult result = solve_step(newton, problem, a, options);
  ASSERT_TRUE(is_converged(result.status)) << to_string(result.status);
  const auto& r = result.gradient_norms;
  std::printf("Newton ||g_k||/||g_0||:");
  for (double n : r) std::printf(" %.2e", n / r.front());
  std::printf("\n");
  // Newton's local convergence: once ||g|| < 1e-2 ||g_0||, every step gains at least three
  // orders of magnitude, and the trust region never stood in the way.
  std::size_t k = 0;
  while (r[k] > 1e-2 * r.front()) ++k;
  EXPECT_LE(r.size() - 1 - k, 3u);
  // (above ||g||'s rounding floor, ~1e-13 ||g_0|| here, where a last step may only halve it)
  for (; k + 1 < r.size() && r[k + 1] > 1e-11 * r.front(); ++k) EXPECT_LT(r[k + 1], 1e-3 * r[k]);
  EXPECT_EQ(newton.counters().rejected_trials, 0);
  EXPECT_EQ(newton.counters().negative_curvature, 0);
}

// The reference stops on the residual acceleration max_i |g_i| / (m_i dt^2): below the
// tolerance at the end, above it one iteration earlier.
TEST(NewtonSolver, StopsOnTheResidualAcceleration) {
  const Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
  StepProblem problem(objective, handles);
  for (double tolerance : {1e-2, 1e-4, 1e-7}) {
    VecX a = VecX::Zero(grid.dof_count());
    NewtonOptimizer newton;
    InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
    options.acceleration_tolerance = tolerance;
    const InnerSolveResult result = solve_step(newton, problem, a, options);
    ASSERT_EQ(result.status, SolveStatus::Converged) << tolerance;
    VecX g;
    problem.value_gradient(a, g);
    EXPECT_LE(objective.residual_acceleration(g), tolerance);
    // One iteration less does not reach it.
    VecX b = VecX::Zero(grid.dof_count());
    NewtonOptimizer shorter;
    InnerSolveOptions capped = options;
    capped.max_iterations = result.iterations - 1;
    solve_step(shorter, problem, b, capped);
    problem.value_gradient(b, g);
    EXPECT_GT(objective.residual_acceleration(g), tolerance);
  }
}

// A factor kept across iterations and time steps (the default) preconditions CG to the same
// converged steps as a fresh factor at every iteration, with far fewer factorizations.
TEST(NewtonSolver, AKeptFactorGivesTheSameStepsWithFewerFactorizations) {
  NewtonOptimizer fresh(fresh_factor_every_iteration()), kept;
  const SideBySide iterations = solve_side_by_side(12, fresh, kept);
  long fresh_iterations = 0, kept_iterations = 0;
  for (std::size_t k = 0; k < iterations.reference.size(); ++k) {
    fresh_iterations += iterations.reference[k];
    kept_iterations += iterations.other[k];
  }
  EXPECT_LT(kept.counters().factorizations, kept_iterations / 4);
  EXPECT_EQ(fresh.counters().factorizations, fresh_iterations);
}

// The most CG products of one iteration that reused P's factor from an earlier iterate (no build in
// it) and took its first trial.
class ReusedFactorProducts final : public InnerOptimizer {
 public:
  explicit ReusedFactorProducts(NewtonOptimizer& newton) : newton_(newton) {}
  std::string name() const override { return newton_.name(); }
  std::string settings() const override { return newton_.settings(); }
  void begin_step(StepProblem& p, const VecX& a, double value, const VecX& g) override {
    newton_.begin_step(p, a, value, g);
  }
  std::optional<SolveStatus> iterate(StepProblem& p, VecX& a, double& value, VecX& g) override {
    const NewtonCounters before = newton_.counters();
    const auto status = newton_.iterate(p, a, value, g);
    const NewtonCounters& after = newton_.counters();
    if (after.factorizations == before.factorizations && after.rejected_trials == before.rejected_trials)
      most = std::max(most, after.cg_iterations - before.cg_iterations);
    return status;
  }
  long most = 0;

 private:
  NewtonOptimizer& newton_;
};

// CG on P's factor from an earlier iterate stops once it is stale (refactor_cg_iterations + 1
// products) and takes the truncated step. On the benchmark scene at 24^2 (its handles start moving at
// frame 30, where the previous step's factor needs more): CG on a reused factor reaches the cap and
// stops there, and every step still converges to the reference's stop.
TEST(NewtonSolver, CgStopsOnAStaleFactorAndEveryStepConverges) {
  NewtonOptimizer newton;
  ReusedFactorProducts probe(newton);
  Scene scene;
  scene.rows = scene.cols = 24;
  scene.frames = 70;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult rollout = run_rollout(resolve(scene), probe, options);
  const long cap = NewtonParams{}.refactor_cg_iterations + 1;
  EXPECT_EQ(probe.most, cap) << "the test must have stale factors for the truncation to mean anything";
  EXPECT_EQ(rollout.converged_steps(), static_cast<int>(rollout.steps.size()));
  EXPECT_TRUE(rollout.positions.back().allFinite());
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
  ASSERT_EQ(solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options()).status, SolveStatus::Converged);
  EXPECT_EQ(a.segment<3>(0), before.segment<3>(0));
  EXPECT_EQ(a.segment<3>(21), before.segment<3>(21));
  EXPECT_GT((a - before).norm(), 0.0);
}

// A cloth compressed to 97 % along its rows, at rest in the xz plane but for a small random
// out-of-plane wrinkle: the exact Hessian is indefinite (compressed springs have negative
// transverse curvature), and the wrinkle gives the gradient a component along the buckling modes.
struct CompressedCloth {
  Grid grid = Grid::make(14, 14, 1.0);
  Material material;
  std::unique_ptr<BackwardEulerObjective> objective;
  DirichletSet handles{grid.vertex_count(), {0, grid.cols - 1}};
  VecX x;

  explicit CompressedCloth(double wrinkle) {
    material.stretch = 800.0;
    material.shear = 3.0;
    material.damping = 0.0;
    objective = std::make_unique<BackwardEulerObjective>(grid, material, 1.0 / 60.0, Vec3(0, 0, -9.81));
    x = grid.rest_positions();
    std::srand(7);
    for (int k = 0; k < grid.vertex_count(); ++k) {
      x[3 * k] *= 0.97;
      x[3 * k + 1] = wrinkle * (std::rand() / double(RAND_MAX) - 0.5);
    }
    objective->begin_step(x, VecX::Zero(grid.dof_count()));
  }
};

// CG meets the negative curvature and follows it, and the step ends buckled, at a point where
// the Hessian is positive definite (a minimum).
TEST(NewtonSolver, ABucklingStepFollowsNegativeCurvatureToAMinimum) {
  CompressedCloth cloth(1e-3);
  StepProblem problem(*cloth.objective, cloth.handles);
  VecX a = VecX::Zero(cloth.grid.dof_count());
  ASSERT_FALSE(hessian_is_definite(*cloth.objective, cloth.handles, a));
  NewtonOptimizer newton;
  const InnerSolveResult result = solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
  std::printf("buckling step: %d iterations, %ld along negative curvature, %ld rejected trials, %ld factorizations\n",
              result.iterations, newton.counters().negative_curvature, newton.counters().rejected_trials,
              newton.counters().factorizations);
  EXPECT_EQ(result.status, SolveStatus::Converged) << to_string(result.status);
  EXPECT_GT(newton.counters().negative_curvature, 0);
  EXPECT_LT(result.value, result.initial_value);
  EXPECT_TRUE(hessian_is_definite(*cloth.objective, cloth.handles, a));
  EXPECT_LE(result.iterations, 60);
}

// A step of 12^2 xz_v2 after the handles have squeezed the cloth in its plane (frame 45): the
// gradient keeps the plane's symmetry, so the reference converges onto the unbuckled saddle
// (docs/design.md §6); newton-min leaves it along the negative pivots' direction and ends at a
// minimum, lower.
TEST(NewtonSolver, NewtonMinLeavesTheSaddleTheReferenceEndsAt) {
  Scene scene;
  scene.rows = scene.cols = 12;
  scene.frames = 45;
  scene.motion = "xz_v2";
  const ResolvedScene resolved = resolve(scene);
  NewtonOptimizer reference;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult rollout = run_rollout(resolved, reference, options);
  ASSERT_FALSE(rollout.diverged);
  // The state of the last frame and the step from it, as the rollout would take it next.
  const VecX x = rollout.positions.back().cast<double>();
  const VecX v = (x - rollout.positions[rollout.positions.size() - 2].cast<double>()) / scene.dt;
  BackwardEulerObjective objective(resolved.grid, resolved.scene.material, scene.dt, resolved.scene.gravity);
  const DirichletSet handles(resolved.grid.vertex_count(), resolved.handles.vertices);
  StepProblem problem(objective, handles);
  std::vector<Vec3> targets;
  for (std::size_t h = 0; h < resolved.handles.vertices.size(); ++h)
    targets.push_back(resolved.trajectory->position(static_cast<int>(h), (scene.frames + 1) * scene.dt));
  auto solve = [&](NewtonParams params, VecX& a, NewtonCounters& counters) {
    objective.begin_step(x, v);
    a = VecX::Zero(resolved.grid.dof_count());
    handles.prescribe(a, x, v, targets, scene.dt);
    NewtonOptimizer newton(params);
    const InnerSolveResult result = solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
    counters = newton.counters();
    return result;
  };
  VecX at_saddle, at_minimum;
  NewtonCounters reference_counters, min_counters;
  const InnerSolveResult saddle = solve(NewtonParams{}, at_saddle, reference_counters);
  NewtonParams seek_minimum;
  seek_minimum.escape_saddles = true;
  const InnerSolveResult minimum = solve(seek_minimum, at_minimum, min_counters);
  std::printf("squeezed step: reference L %.10g in %d iterations, newton-min L %.10g in %d (%ld escapes)\n",
              saddle.value, saddle.iterations, minimum.value, minimum.iterations, min_counters.saddle_escapes);
  ASSERT_EQ(saddle.status, SolveStatus::Converged);
  ASSERT_EQ(minimum.status, SolveStatus::Converged);
  EXPECT_EQ(reference_counters.saddle_escapes, 0);
  EXPECT_FALSE(hessian_is_definite(objective, handles, at_saddle));
  EXPECT_GT(min_counters.saddle_escapes, 0);
  EXPECT_TRUE(hessian_is_definite(objective, handles, at_minimum));
  EXPECT_LT(minimum.value, saddle.value);
  EXPECT_EQ(NewtonOptimizer(seek_minimum).name(), "newton-min");
}

// The factor's float copy in bfloat16 (large factors' default, forced here on a small one) is a
// coarser preconditioner: CG takes a few more products, the steps are the same to the tolerance.
TEST(NewtonSolver, ABfloat16FactorGivesTheSameSteps) {
  NewtonParams in_floats, in_bfloat16;
  in_floats.bfloat16_factor_from_entries = 1L << 40;
  in_bfloat16.bfloat16_factor_from_entries = 0;
  NewtonOptimizer floats(in_floats), bfloat16(in_bfloat16);
  const SideBySide iterations = solve_side_by_side(16, floats, bfloat16);
  for (std::size_t k = 0; k < iterations.reference.size(); ++k)
    EXPECT_LE(std::abs(iterations.other[k] - iterations.reference[k]), 1) << "step " << k;
  const long float_products = floats.counters().cg_iterations;
  const long bfloat16_products = bfloat16.counters().cg_iterations;
  std::printf("CG products over 20 steps: float factor %ld, bfloat16 factor %ld\n", float_products, bfloat16_products);
  EXPECT_LT(bfloat16_products, 1.5 * float_products);
}

// A multigrid V-cycle in place of P's factor (fine grids' default) changes CG's path, not the
// steps: the same accelerations to the tolerance, without a factorisation of P.
TEST(NewtonSolver, AMultigridPreconditionerGivesTheSameSteps) {
  NewtonParams with_factor, with_multigrid;
  with_factor.multigrid_from_dofs = 1 << 30;
  with_multigrid.multigrid_from_dofs = 0;
  NewtonOptimizer factor(with_factor), multigrid(with_multigrid);
  solve_side_by_side(24, factor, multigrid);
  const long factor_products = factor.counters().cg_iterations;
  const long multigrid_products = multigrid.counters().cg_iterations;
  std::printf("CG products over 20 steps: factor %ld, multigrid %ld\n", factor_products, multigrid_products);
  // A V-cycle approximates P^-1, so CG needs more products, but not many more.
  EXPECT_LT(multigrid_products, 3 * factor_products);
  EXPECT_GT(multigrid.counters().factorizations, 0);  // P rebuilt (the V-cycle's levels) as often as needed
}

// Where a fresh V-cycle leaves CG at its cap, the factor takes over and the step converges where the
// factor's does (the cap forced low here; on very stiff cloth the cycle itself is too weak).
TEST(NewtonSolver, AMultigridThatLeavesCgAtItsCapGivesWayToTheFactor) {
  NewtonParams with_factor, with_multigrid;
  with_factor.multigrid_from_dofs = 1 << 30;
  with_multigrid.multigrid_from_dofs = 0;
  with_factor.max_cg_iterations = with_multigrid.max_cg_iterations = 2;
  NewtonOptimizer factor(with_factor), multigrid(with_multigrid);
  solve_side_by_side(16, factor, multigrid);
  EXPECT_EQ(multigrid.counters().multigrid_fallbacks, 1);
  EXPECT_EQ(factor.counters().multigrid_fallbacks, 0);
}

// Records each iterate Newton leaves, before solve_step's no-penetration filter sees it.
class RecordedNewton final : public InnerOptimizer {
 public:
  std::string name() const override { return newton.name(); }
  std::string settings() const override { return newton.settings(); }
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override {
    newton.begin_step(problem, a, value, gradient);
  }
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    const VecX before = a;
    const double before_value = value;
    auto stop = newton.iterate(problem, a, value, gradient);
    if (!stop) moves.push_back({before, a, before_value, value});
    return stop;
  }
  struct Move {
    VecX from, to;
    double from_value, to_value;
  };
  NewtonOptimizer newton;
  std::vector<Move> moves;
};

// A cloth falling fast onto a plate thinner than one step's fall: the first trials, taken where the
// model sees no contact yet, end beyond the plate at a lower L. Each iterate Newton takes is reached
// on a feasible path and lowers L: the trust region judges the cut trial, not the point past the
// plate that the filter would pull back.
TEST(NewtonSolver, WithContactEachIterateIsFeasibleAndLowersTheEnergy) {
  const Grid grid = Grid::make(8, 8, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81),
                                   parse_obstacles("box center=0,0,-0.202 size=2,2,0.004 rounding=0.001"));
  const DirichletSet none(grid.vertex_count(), {});
  StepProblem problem(objective, none);
  VecX v = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k + 2] = -15.0;  // 25 cm a step, the plate 20 cm down
  objective.begin_step(placed_rest_positions(grid, Placement::Horizontal), v, 0.0);
  RecordedNewton newton;
  VecX a = -v / objective.dt();  // from the cloth where it is, out of the barrier's range
  const InnerSolveResult result = solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
  EXPECT_EQ(result.status, SolveStatus::Converged);
  ASSERT_GE(newton.moves.size(), 2u);
  for (std::size_t k = 0; k < newton.moves.size(); ++k) {
    const RecordedNewton::Move& move = newton.moves[k];
    EXPECT_EQ(problem.feasible_fraction(move.from, move.to), 1.0) << "iterate " << k;
    EXPECT_LT(move.to_value, move.from_value) << "iterate " << k;
  }
  VecX x;
  objective.trial_positions(a, x);
  for (int k = 0; k < grid.vertex_count(); ++k) EXPECT_GT(x[3 * k + 2], -0.2) << "vertex " << k;
}

// With self-contact the preconditioner is rebuilt at every step's start (the cloth's pairs in range
// change from step to step); with obstacles alone, a kept factor serves several steps.
TEST(NewtonSolver, WithSelfContactEveryStepStartsFromAFreshPreconditioner) {
  const Grid grid = Grid::make(8, 8, 1.0);
  auto factorizations = [&](bool self_contact) {
    BackwardEulerObjective objective(
        grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81), parse_obstacles("plane point=0,0,-0.01 normal=0,0,1"), {},
        self_contact ? std::optional<SelfContactParams>(SelfContactParams{}) : std::nullopt);
    const DirichletSet none(grid.vertex_count(), {});
    StepProblem problem(objective, none);
    NewtonOptimizer newton;
    VecX x = placed_rest_positions(grid, Placement::Horizontal), v = VecX::Zero(grid.dof_count());
    const int steps = 12;
    for (int step = 0; step < steps; ++step) {
      objective.begin_step(x, v, step * objective.dt());
      VecX a = VecX::Zero(grid.dof_count());
      problem.make_start_feasible(a);
      EXPECT_EQ(solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options()).status,
                SolveStatus::Converged);
      v += objective.dt() * a;
      x += objective.dt() * v;
    }
    return std::pair<long, int>(newton.counters().factorizations, steps);
  };
  const auto [with_self_contact, steps] = factorizations(true);
  EXPECT_GE(with_self_contact, steps);
  const auto [obstacles_only, same_steps] = factorizations(false);
  EXPECT_LT(obstacles_only, same_steps);
}

TEST(NewtonParams, EveryParameterChangesTheSettingsString) {
  const std::string base = NewtonOptimizer{}.settings();
  const std::vector<void (*)(NewtonParams&)> changes = {[](NewtonParams& p) { p.initial_radius = 3.0; },
                                                        [](NewtonParams& p) { p.accept_ratio = 1e-3; },
                                                        [](NewtonParams& p) { p.shrink_below = 0.2; },
                                                        [](NewtonParams& p) { p.shrink = 0.3; },
                                                        [](NewtonParams& p) { p.grow_above = 0.8; },
                                                        [](NewtonParams& p) { p.max_trials = 30; },
                                                        [](NewtonParams& p) { p.forcing_cap = 2e-2; },
                                                        [](NewtonParams& p) { p.acceleration_tolerance = 1e-5; },
                                                        [](NewtonParams& p) { p.max_cg_iterations = 100; },
                                                        [](NewtonParams& p) { p.refactor_cg_iterations = 10; },
                                                        [](NewtonParams& p) { p.reuse_factor_across_steps = false; },
                                                        [](NewtonParams& p) { p.bfloat16_factor_from_entries = 0; },
                                                        [](NewtonParams& p) { p.multigrid_from_dofs = 0; },
                                                        [](NewtonParams& p) { p.multigrid.smoothing_sweeps = 2; },
                                                        [](NewtonParams& p) { p.multigrid.coarsest_dofs = 100; },
                                                        [](NewtonParams& p) { p.escape_saddles = true; }};
  for (std::size_t i = 0; i < changes.size(); ++i) {
    NewtonParams params;
    changes[i](params);
    EXPECT_NE(NewtonOptimizer(params).settings(), base) << "change " << i;
  }
}

TEST(NewtonParams, RejectsInvalidValues) {
  const std::vector<std::pair<void (*)(NewtonParams&), std::string>> bad = {
      {[](NewtonParams& p) { p.initial_radius = 0.0; }, "newton.initial_radius"},
      {[](NewtonParams& p) { p.accept_ratio = 0.5; }, "newton.accept_ratio"},
      {[](NewtonParams& p) { p.shrink_below = 0.9; }, "newton.shrink_below"},
      {[](NewtonParams& p) { p.grow_above = 1.0; }, "newton.grow_above"},
      {[](NewtonParams& p) { p.shrink = 1.0; }, "newton.shrink"},
      {[](NewtonParams& p) { p.max_trials = 0; }, "newton.max_trials"},
      {[](NewtonParams& p) { p.forcing_cap = 1.0; }, "newton.forcing_cap"},
      {[](NewtonParams& p) { p.acceleration_tolerance = 0.0; }, "newton.acceleration_tolerance"},
      {[](NewtonParams& p) { p.max_cg_iterations = 0; }, "newton.max_cg_iterations"},
      {[](NewtonParams& p) { p.refactor_cg_iterations = -1; }, "newton.refactor_cg_iterations"},
      {[](NewtonParams& p) { p.max_saddle_escapes = -1; }, "newton.max_saddle_escapes"},
      {[](NewtonParams& p) { p.multigrid_from_dofs = -1; }, "newton.multigrid_from_dofs"},
      {[](NewtonParams& p) { p.bfloat16_factor_from_entries = -1; }, "newton.bfloat16_factor_from_entries"},
      {[](NewtonParams& p) { p.multigrid.smoothing_sweeps = 0; }, "multigrid.smoothing_sweeps"}};
  for (const auto& [change, field] : bad) {
    NewtonParams p;
    change(p);
    try {
      NewtonOptimizer newton(p);
      ADD_FAILURE() << field << " accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace fnopt
