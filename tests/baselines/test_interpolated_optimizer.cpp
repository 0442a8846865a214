// The interpolation ablation (baselines/interpolated_optimizer.hpp): with Newton on a coarse
// grid equal to the fine one it is the Newton step; handles never move; on a smooth state of a
// finer grid its answer lowers the step energy from a = 0.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/baselines/interpolated_optimizer.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

const Vec3 kGravity(0, 0, -9.81);
constexpr double kDt = 1.0 / 60.0;

// A step of `grid` hanging from its two top corners, swinging sideways (a smooth velocity
// field), with the corners pulled along x.
struct Step {
  Grid grid;
  Material material;
  BackwardEulerObjective objective;
  DirichletSet handles;
  StepProblem problem;
  VecX a0;

  Step(int rows, int cols)
      : grid(Grid::make(rows, cols, 1.0)),
        objective(grid, material, kDt, kGravity),
        handles(grid.vertex_count(), {grid.index(0, 0), grid.index(0, grid.cols - 1)}),
        problem(objective, handles) {
    VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count());
    for (int i = 0; i < grid.rows; ++i)
      for (int j = 0; j < grid.cols; ++j) {
        const double s = static_cast<double>(i) / (grid.rows - 1), t = static_cast<double>(j) / (grid.cols - 1);
        v[3 * grid.index(i, j)] = 0.8 * s * std::sin(M_PI * t);
        v[3 * grid.index(i, j) + 1] = 0.3 * s * s;
      }
    objective.begin_step(x, v);
    a0 = VecX::Zero(grid.dof_count());
    std::vector<Vec3> targets;
    for (int h : handles.fixed_vertices()) targets.push_back(vertex(x, h) + Vec3(0.002, 0.0, 0.0005));
    handles.prescribe(a0, x, v, targets, kDt);
  }
};

InterpolatedOptimizer interpolated_newton(int coarse_size) {
  InterpolatedParams params;
  params.coarse_size = coarse_size;
  params.coarse_solve = NewtonOptimizer::reference_solve_options();
  return InterpolatedOptimizer([] { return std::make_unique<NewtonOptimizer>(); }, params);
}

TEST(InterpolatedOptimizer, NewtonOnTheSameGridIsTheNewtonStep) {
  for (const auto& [rows, cols] : {std::pair{12, 12}, std::pair{10, 14}}) {
    Step step(rows, cols);
    NewtonOptimizer newton;
    VecX exact = step.a0;
    ASSERT_EQ(solve_step(newton, step.problem, exact, NewtonOptimizer::reference_solve_options()).status,
              SolveStatus::Converged);
    InterpolatedOptimizer interp = interpolated_newton(std::max(rows, cols));
    EXPECT_EQ(interp.name(), "newton-interp" + std::to_string(std::max(rows, cols)));
    VecX a = step.a0;
    const InnerSolveResult r = solve_step(interp, step.problem, a, {1, 0.0});
    EXPECT_EQ(interp.coarse_grid().rows, rows);
    EXPECT_EQ(interp.coarse_grid().cols, cols);
    EXPECT_EQ(interp.last_coarse_solve().status, SolveStatus::Converged);
    EXPECT_EQ(r.iterations, 1);
    EXPECT_LT((a - exact).norm(), 1e-9 * exact.norm()) << rows << "x" << cols;
    EXPECT_NEAR(r.value, step.problem.value(exact), 1e-12 * std::abs(r.value) + 1e-15);
  }
}

TEST(InterpolatedOptimizer, HandlesNeverMoveAndASecondIterationChangesNothing) {
  Step step(21, 21);
  InterpolatedOptimizer interp = interpolated_newton(8);
  VecX a = step.a0;
  const InnerSolveResult r = solve_step(interp, step.problem, a, {5, 0.0});
  EXPECT_EQ(r.status, SolveStatus::Converged);  // the answer, then nothing more to do
  EXPECT_EQ(r.iterations, 1);
  for (int h : step.handles.fixed_vertices()) EXPECT_EQ(a.segment<3>(3 * h), step.a0.segment<3>(3 * h));
  EXPECT_TRUE(a.allFinite());
}

TEST(InterpolatedOptimizer, OnAFinerGridItsAnswerLowersTheStepEnergy) {
  for (const auto& [rows, cols, coarse] : {std::tuple{24, 24, 12}, std::tuple{16, 30, 12}, std::tuple{33, 20, 10}}) {
    Step step(rows, cols);
    InterpolatedOptimizer interp = interpolated_newton(coarse);
    VecX a = step.a0;
    const InnerSolveResult r = solve_step(interp, step.problem, a, {1, 0.0});
    EXPECT_LT(r.value, r.initial_value) << rows << "x" << cols << " from " << coarse;
    EXPECT_EQ(std::max(interp.coarse_grid().rows, interp.coarse_grid().cols), coarse);
  }
}

TEST(InterpolatedOptimizer, RunsARolloutLikeAnyOtherMethod) {
  Scene scene;
  scene.rows = 16;
  scene.cols = 20;
  scene.frames = 10;
  InterpolatedOptimizer interp = interpolated_newton(10);
  RolloutOptions options;
  options.solve = {1, 0.0};
  const RolloutResult r = run_rollout(resolve(scene), interp, options);
  EXPECT_FALSE(r.diverged) << r.divergence;
  EXPECT_EQ(r.steps.size(), 10u);
  EXPECT_EQ(r.total_iterations(), 10);
}

TEST(InterpolatedOptimizer, RejectsInvalidSettings) {
  InterpolatedParams params;
  params.coarse_size = 2;
  EXPECT_THROW(InterpolatedOptimizer([] { return std::make_unique<NewtonOptimizer>(); }, params), Error);
  EXPECT_THROW(InterpolatedOptimizer(InnerOptimizerFactory{}), Error);
}

}  // namespace
}  // namespace fnopt
