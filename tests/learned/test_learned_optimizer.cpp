// The learned optimizer: runs on odd and non-square grids, never moves handles, rejects bad
// model files, and the shipped model lowers the energy of a real step.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <tuple>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/learned_optimizer.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>
#include "tests/learned/step_probes.hpp"

namespace fnopt {
namespace {

// combined: one sample with x, y, z as channels (9 in, 3 out) instead of three samples.
FNO2d tiny_model(bool combined = false) {
  torch::manual_seed(3);
  return FNO2d(FNO2dOptions()
                   .width(4)
                   .fourier_layers(2)
                   .modes_x(4)
                   .modes_y(4)
                   .lifting_channels(8)
                   .projection_channels(4)
                   .in_channels(combined ? 9 : 3)
                   .out_channels(combined ? 3 : 1));
}

// One time step of a falling cloth with two corner handles and a third moving handle.
struct Step {
  Grid grid;
  BackwardEulerObjective objective;
  DirichletSet handles;
  StepProblem problem{objective, handles};
  VecX a;
  Step(int rows, int cols)
      : grid(Grid::make(rows, cols, 1.0)),
        objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81)),
        handles(grid.vertex_count(), {0, cols - 1, grid.index(rows / 2, cols / 2)}) {
    VecX v = VecX::Zero(grid.dof_count());
    for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k + 1] = 0.5 * (k % cols) / cols;
    objective.begin_step(grid.rest_positions(), v);
    a = VecX::Zero(grid.dof_count());
    handles.prescribe(
        a, grid.rest_positions(), v,
        {Vec3(0, 0.01, 0), Vec3(1, 0, 0.01), vertex(grid.rest_positions(), grid.index(rows / 2, cols / 2))},
        1.0 / 60.0);
  }
};

LearnedParams with_safeguard(bool on) {
  LearnedParams params;
  params.safeguard = on;
  return params;
}

TEST(LearnedOptimizer, TinyRandomModelRunsOnOddAndNonSquareGridsAndNeverMovesHandles) {
  for (auto [rows, cols, combined] : {std::tuple{17, 23, false}, std::tuple{40, 40, false}, std::tuple{17, 23, true}}) {
    Step step(rows, cols);
    // Without the safeguard every update of the untrained model is applied: the free
    // vertices move, the handles must not.
    LearnedOptimizer optimizer(tiny_model(combined), "tiny", with_safeguard(false));
    const VecX before = step.a;
    const InnerSolveResult result = solve_step(optimizer, step.problem, step.a, {10, 0.0});
    EXPECT_EQ(result.status, SolveStatus::IterationBudget);
    EXPECT_EQ(result.iterations, 10);
    EXPECT_TRUE(step.a.allFinite());
    EXPECT_GT((step.a - before).norm(), 0.0);
    for (int k : step.handles.fixed_vertices())
      EXPECT_EQ(step.a.segment<3>(3 * k), before.segment<3>(3 * k)) << rows << "x" << cols << " handle " << k;
  }
}

TEST(LearnedOptimizer, SafeguardNeverLetsTheEnergyRise) {
  // An untrained model proposes poor updates: with the safeguard L never increases, without
  // it, it does.
  for (bool safeguard : {true, false}) {
    Step step(20, 20);
    LearnedOptimizer learned(tiny_model(), "tiny", with_safeguard(safeguard));
    EnergyLog log(learned);
    solve_step(log, step.problem, step.a, {30, 0.0});
    int rises = 0;
    for (std::size_t k = 1; k < log.values.size(); ++k) rises += log.values[k] > log.values[k - 1];
    if (safeguard)
      EXPECT_EQ(rises, 0);
    else
      EXPECT_GT(rises, 0) << "the test model must make bad updates for this test to mean anything";
  }
}

TEST(LearnedOptimizer, LineSearchEndsEachUpdateNearTheMinimumAlongIt) {
  // With the secant step, the slope along an accepted update is near 0 at its end (exactly 0
  // for a quadratic L; a rescale is skipped for |alpha - 1| <= 0.2, which leaves at most
  // 1 - 1/1.2 of it); the energy still never rises.
  const std::string path = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";
  double worst[2] = {0.0, 0.0};
  for (bool line_search : {false, true}) {
    Step step(32, 32);
    LearnedParams params;
    params.line_search = line_search;
    LearnedOptimizer learned(path, params);
    EXPECT_EQ(learned.name(), line_search ? "fnopt-ls" : "fnopt-plain");
    EnergyLog log(learned);
    solve_step(log, step.problem, step.a, {10, 0.0});
    for (std::size_t k = 1; k < log.values.size(); ++k) EXPECT_LE(log.values[k], log.values[k - 1]);
    ASSERT_GE(log.slope_ratios.size(), 5u);
    for (double r : log.slope_ratios) worst[line_search] = std::max(worst[line_search], std::abs(r));
  }
  std::printf("largest |slope after / slope before|: %.3f without, %.3f with the line search\n", worst[0], worst[1]);
  EXPECT_LT(worst[1], 0.3);
  EXPECT_GT(worst[0], worst[1]) << "the test step must have updates that the line search rescales";
}

TEST(LearnedOptimizer, SubspaceStepLeavesLessErrorThanTheSecantStepAlongANewtonTrajectory) {
  // Along the Newton rollout of the 32^2 benchmark scene, each step solved with N = 10 from the
  // same start: the subspace step (fnopt-ss) leaves less of the energy the steps had to remove,
  // sum_t (L_N - L*) / sum_t (L_0 - L*), than the secant step (fnopt-ls), and carrying its pairs
  // across steps leaves less than clearing them. The sums weight each step by its own decrease:
  // in the first 30 steps the cloth settles towards rest (L_0 - L* down to 1e-7), the methods
  // often end below Newton's L* in another local minimum of the buckling cloth (counted as no
  // error, not as negative error), and a plain mean of per-step ratios there followed the BLAS's
  // rounding (OpenBLAS's Haswell and AVX-512 kernels ranked fnopt-ss-pqn and fnopt-ss in opposite
  // orders over 40 steps). The 50 steps after it, with the handles moving, decide.
  const std::string path = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";
  LearnedParams secant, carried, cleared, with_pqn;
  secant.line_search = true;
  carried.subspace = cleared.subspace = with_pqn.subspace = 8;
  cleared.carry_subspace = false;
  with_pqn.pqn_direction = true;
  LearnedOptimizer ls(path, secant), ss(path, carried), ss_cleared(path, cleared), ss_pqn(path, with_pqn);
  EXPECT_EQ(ss.name(), "fnopt-ss");
  EXPECT_EQ(ss_pqn.name(), "fnopt");
  NewtonOptimizer newton;
  Shadows shadows(newton, {&ls, &ss, &ss_cleared, &ss_pqn}, {10, 0.0});
  Scene scene;
  scene.rows = scene.cols = 32;
  scene.frames = 80;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult r = run_rollout(resolve(scene), shadows, options);
  ASSERT_EQ(r.steps.size(), 80u);
  double left[4] = {0.0, 0.0, 0.0, 0.0}, to_remove = 0.0;
  for (std::size_t t = 0; t < r.steps.size(); ++t) {
    to_remove += r.steps[t].initial_loss - r.steps[t].loss;
    for (int k = 0; k < 4; ++k) {
      ASSERT_LE(shadows.values[k][t], r.steps[t].initial_loss) << "step " << t << ": the safeguard lets no step rise";
      left[k] += std::max(0.0, shadows.values[k][t] - r.steps[t].loss);
    }
  }
  for (double& l : left) l /= to_remove;
  std::printf(
      "share of the energy left over %zu steps: fnopt-ls %.4f, fnopt-ss %.4f, fnopt-ss without carrying %.4f, "
      "fnopt-ss-pqn %.4f\n",
      r.steps.size(), left[0], left[1], left[2], left[3]);
  EXPECT_LT(left[1], left[0]);
  EXPECT_LT(left[1], left[2]);
  // pqn's direction in the subspace: the FNO's directions and A's together do better than the
  // FNO's alone.
  EXPECT_LT(left[3], left[1]);
}

TEST(LearnedOptimizer, PqnDirectionNeedsTheSubspaceStepAndNeverMovesHandles) {
  LearnedParams params;
  params.pqn_direction = true;
  try {
    LearnedOptimizer optimizer(tiny_model(), "tiny", params);
    FAIL() << "pqn_direction without the subspace step was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "fnopt.pqn_direction");
  }
  // On two grids in turn (A's factor is rebuilt for the second): L never rises, handles stay.
  params.subspace = 4;
  LearnedOptimizer optimizer(tiny_model(), "tiny", params);
  EXPECT_NE(optimizer.settings().find("pqn_direction=isotropic"), std::string::npos) << optimizer.settings();
  for (auto [rows, cols] : {std::pair{17, 23}, std::pair{24, 24}}) {
    Step step(rows, cols);
    const VecX before = step.a;
    EnergyLog log(optimizer);
    solve_step(log, step.problem, step.a, {10, 0.0});
    for (std::size_t k = 1; k < log.values.size(); ++k) EXPECT_LE(log.values[k], log.values[k - 1]);
    EXPECT_LT(log.values.back(), log.values.front());
    for (int k : step.handles.fixed_vertices()) EXPECT_EQ(step.a.segment<3>(3 * k), before.segment<3>(3 * k));
  }
}

TEST(LearnedOptimizer, CarriedSubspaceIsClearedWhenTheGridChanges) {
  // One optimizer on 17x23, then 40x40, then 17x23 again: the pairs carried from another grid
  // have other sizes and must not be used.
  LearnedParams params;
  params.subspace = 3;
  LearnedOptimizer optimizer(tiny_model(), "tiny", params);
  for (auto [rows, cols] : {std::pair{17, 23}, std::pair{40, 40}, std::pair{17, 23}}) {
    Step step(rows, cols);
    const VecX before = step.a;
    const InnerSolveResult result = solve_step(optimizer, step.problem, step.a, {10, 0.0});
    EXPECT_TRUE(step.a.allFinite());
    EXPECT_LE(result.value, result.initial_value);
    for (int k : step.handles.fixed_vertices()) EXPECT_EQ(step.a.segment<3>(3 * k), before.segment<3>(3 * k));
  }
}

TEST(LearnedOptimizer, CarriedSubspaceReachesOnlyTheStepThatContinuesTheLastOne) {
  // Two optimizers that differ only in carrying the subspace solve the same three steps of one
  // problem: a step, an unrelated state (the same start again, as the per-step error bench
  // would give), and the step that continues it. Only the continuation may see the pairs.
  const std::string path = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";
  LearnedParams carried, cleared;
  carried.subspace = cleared.subspace = 6;
  cleared.carry_subspace = false;
  LearnedOptimizer with(path, carried), without(path, cleared);
  LearnedOptimizer* optimizers[2] = {&with, &without};
  Step step(32, 32);
  const VecX x0 = step.objective.start_positions(), v0 = step.objective.start_velocities(), a0 = step.a;
  VecX a_first[2], a_again[2], a_next[2];
  for (int k = 0; k < 2; ++k) {
    step.objective.begin_step(x0, v0);
    a_first[k] = a0;
    solve_step(*optimizers[k], step.problem, a_first[k], {10, 0.0});
    step.objective.begin_step(x0, v0);
    a_again[k] = a0;
    solve_step(*optimizers[k], step.problem, a_again[k], {10, 0.0});
  }
  EXPECT_EQ(a_first[0], a_first[1]);
  EXPECT_EQ(a_again[0], a_again[1]) << "pairs were carried into an unrelated state";
  // The continuation: v_1 = v_0 + dt a, x_1 = x_0 + dt v_1, the handles moving on.
  const double dt = step.objective.dt();
  const VecX v1 = v0 + dt * a_again[0], x1 = x0 + dt * v1;
  for (int k = 0; k < 2; ++k) {
    step.objective.begin_step(x1, v1);
    a_next[k] = a0;
    solve_step(*optimizers[k], step.problem, a_next[k], {10, 0.0});
  }
  EXPECT_NE(a_next[0], a_next[1]) << "the continuing step did not use the carried pairs";
}

// The shipped model widened to read pqn's direction proposes what it did (the new input's weights
// are zero), so fnopt-ss with either solves a 32^2 step alike; once those weights move, the
// proposals follow the new input, the safeguard still holds L down and the handles stay.
TEST(LearnedOptimizer, AModelThatReadsPqnsDirectionStartsAsTheModelItWidens) {
  const FNO2d shipped = load_learned_model(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt");
  FNO2d widened = with_pqn_direction_input(shipped);
  EXPECT_TRUE(takes_pqn_direction(widened->options));
  EXPECT_EQ(widened->options.in_channels(), 4);
  EXPECT_THROW(with_pqn_direction_input(widened), Error);
  LearnedParams params;
  params.subspace = kFnoptSubspace;
  auto solve = [&](const FNO2d& model, std::string* settings = nullptr) {
    Step step(32, 32);
    LearnedOptimizer optimizer(model, "model", params);
    if (settings) *settings = optimizer.settings();
    EnergyLog log(optimizer);
    const VecX before = step.a;
    solve_step(log, step.problem, step.a, {10, 0.0});
    for (std::size_t k = 1; k < log.values.size(); ++k) EXPECT_LE(log.values[k], log.values[k - 1]);
    for (int k : step.handles.fixed_vertices()) EXPECT_EQ(step.a.segment<3>(3 * k), before.segment<3>(3 * k));
    return std::pair{step.a, log.values.back()};
  };
  std::string settings;
  const auto [a_shipped, value_shipped] = solve(shipped);
  const auto [a_widened, value_widened] = solve(widened, &settings);
  EXPECT_NE(settings.find(" pqn_input"), std::string::npos) << settings;
  EXPECT_LT((a_widened - a_shipped).norm(), 1e-5 * a_shipped.norm());
  EXPECT_NEAR(value_widened, value_shipped, 1e-6 * std::abs(value_shipped));
  {
    torch::NoGradGuard no_grad;
    torch::manual_seed(5);
    for (auto& p : widened->named_parameters())
      if (p.key() == "lift_in.weight") p.value().narrow(1, 3, 1).normal_(0.0, 1.0);
  }
  const auto [a_moved, value_moved] = solve(widened);
  EXPECT_GT((a_moved - a_shipped).norm(), 1e-3 * a_shipped.norm()) << "the new input is not read";
  EXPECT_TRUE(std::isfinite(value_moved));
}

TEST(LearnedOptimizer, ALearnedStepNeedsPqnsDirectionExactlyWhenTheModelReadsIt) {
  const torch::Tensor g = torch::randn({3, 1, 9, 9}), mask = torch::ones({1, 1, 9, 9});
  FNO2d plain = tiny_model(), widened = with_pqn_direction_input(tiny_model());
  EXPECT_NO_THROW(learned_step(plain, g, LearnedState{}, mask));
  EXPECT_THROW(learned_step(plain, g, LearnedState{}, mask, g), Error);
  EXPECT_THROW(learned_step(widened, g, LearnedState{}, mask), Error);
  EXPECT_NO_THROW(learned_step(widened, g, LearnedState{}, mask, g));
  EXPECT_EQ(learned_inputs(g, LearnedState{}, g).size(1), 4);
  FNO2d combined = with_pqn_direction_input(tiny_model(true));
  EXPECT_EQ(combined->options.in_channels(), 12);
  EXPECT_EQ(samples_per_environment(combined->options), 1);
  const torch::Tensor g1 = g.view({1, 3, 9, 9});
  EXPECT_EQ(learned_step(combined, g1, LearnedState{}, mask, g1).delta.sizes(), g1.sizes());
}

// The shipped model widened to read the grid's size proposes what it did; with those weights moved it
// still does at 32^2, where the size fields are zero, and no longer at 20^2. Widened for pqn's
// direction too (6 inputs: pqn's field goes before the size fields), it still proposes what it did.
TEST(LearnedOptimizer, AModelThatReadsTheGridSizeStartsAsTheModelItWidens) {
  const FNO2d shipped = load_learned_model(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt");
  FNO2d widened = with_grid_size_input(shipped);
  EXPECT_TRUE(takes_grid_size(widened->options));
  EXPECT_FALSE(takes_pqn_direction(widened->options));
  EXPECT_EQ(widened->options.in_channels(), 5);
  EXPECT_THROW(with_grid_size_input(widened), Error);
  const FNO2d both = with_pqn_direction_input(widened);
  EXPECT_TRUE(takes_grid_size(both->options) && takes_pqn_direction(both->options));
  LearnedParams params;
  params.subspace = kFnoptSubspace;
  auto solve = [&](const FNO2d& model, int n, std::string* settings = nullptr) {
    Step step(n, n);
    LearnedOptimizer optimizer(model, "model", params);
    if (settings) *settings = optimizer.settings();
    solve_step(optimizer, step.problem, step.a, {10, 0.0});
    return VecX(step.a);
  };
  std::string settings;
  const VecX shipped_32 = solve(shipped, 32), shipped_20 = solve(shipped, 20);
  EXPECT_LT((solve(widened, 32, &settings) - shipped_32).norm(), 1e-5 * shipped_32.norm());
  EXPECT_NE(settings.find(" grid_size_input"), std::string::npos) << settings;
  EXPECT_LT((solve(widened, 20) - shipped_20).norm(), 1e-5 * shipped_20.norm());
  EXPECT_LT((solve(both, 20) - shipped_20).norm(), 1e-5 * shipped_20.norm());
  {
    torch::NoGradGuard no_grad;
    torch::manual_seed(5);
    for (auto& p : widened->named_parameters())
      if (p.key() == "lift_in.weight") p.value().narrow(1, 3, 2).normal_(0.0, 1.0);
  }
  EXPECT_LT((solve(widened, 32) - shipped_32).norm(), 1e-5 * shipped_32.norm());
  EXPECT_GT((solve(widened, 20) - shipped_20).norm(), 1e-3 * shipped_20.norm()) << "the size fields are not read";
}

// The size fields are log2((n - 1)/31) of the rows and of the columns, constant, after the other inputs, in
// either layout.
TEST(LearnedOptimizer, TheGridSizeFieldsAreTheLogOfTheCellCountsOver31) {
  const torch::Tensor g = torch::randn({3, 1, 9, 17}), mask = torch::ones({1, 1, 9, 17});
  const torch::Tensor inputs = learned_inputs(g, LearnedState{}, {}, true);
  ASSERT_EQ(inputs.size(1), 5);
  EXPECT_TRUE(torch::allclose(inputs.narrow(1, 3, 1), torch::full({3, 1, 9, 17}, std::log2(8.0 / 31.0))));
  EXPECT_TRUE(torch::allclose(inputs.narrow(1, 4, 1), torch::full({3, 1, 9, 17}, std::log2(16.0 / 31.0))));
  EXPECT_TRUE(torch::equal(inputs.narrow(1, 0, 3), learned_inputs(g, LearnedState{})));
  FNO2d combined = with_grid_size_input(tiny_model(true));
  EXPECT_EQ(combined->options.in_channels(), 11);
  EXPECT_EQ(with_pqn_direction_input(combined)->options.in_channels(), 14);
  const torch::Tensor g1 = g.view({1, 3, 9, 17});
  EXPECT_EQ(learned_step(combined, g1, LearnedState{}, mask).delta.sizes(), g1.sizes());
  FNO2d per_coordinate = with_grid_size_input(tiny_model());
  EXPECT_EQ(learned_step(per_coordinate, g, LearnedState{}, mask).delta.sizes(), g.sizes());
}

TEST(LearnedOptimizer, RejectsMissingAndIncompatibleModelFiles) {
  EXPECT_THROW(LearnedOptimizer("/nonexistent/model.pt"), Error);
  const auto path = (std::filesystem::temp_directory_path() / "fnopt_test_wrong_model.pt").string();
  save_fno(path,
           FNO2d(FNO2dOptions().in_channels(7).width(4).fourier_layers(2).lifting_channels(4).projection_channels(4)));
  try {
    LearnedOptimizer optimizer(path);
    FAIL() << "a 7-channel FNO was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a learned-optimizer model"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(LearnedOptimizer, ShippedModelLowersTheEnergyOfA32Step) {
  const std::string path = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";
  ASSERT_TRUE(std::filesystem::exists(path)) << "the shipped model is missing: " << path;
  Step step(32, 32);
  LearnedOptimizer optimizer(path);
  const InnerSolveResult result = solve_step(optimizer, step.problem, step.a, {10, 0.0});
  EXPECT_TRUE(std::isfinite(result.value));
  EXPECT_LT(result.value, result.initial_value);
}

}  // namespace
}  // namespace fnopt
