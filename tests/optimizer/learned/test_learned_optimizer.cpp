// The learned optimizer: runs on odd and non-square grids, never moves handles, rejects bad
// model files, and the shipped model lowers the energy of a real step.
#include <gtest/gtest.h>

#include <filesystem>
#include <tuple>

#include "baselines/newton.hpp"
#include "fno/fno_io.hpp"
#include "optimizer/learned/learned_optimizer.hpp"
#include "util/error.hpp"

namespace fnopt {
namespace {

// combined: one sample with x, y, z as channels (9 in, 3 out) instead of three samples.
FNO2d tiny_model(bool combined = false) {
  torch::manual_seed(3);
  return FNO2d(FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4)
                   .in_channels(combined ? 9 : 3).out_channels(combined ? 3 : 1));
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
    handles.prescribe(a, grid.rest_positions(), v, {Vec3(0, 0.01, 0), Vec3(1, 0, 0.01), vertex(grid.rest_positions(), grid.index(rows / 2, cols / 2))}, 1.0 / 60.0);
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

// Records L after every iteration of the wrapped optimizer, and the slope of L along each
// update d = a_after - a_before at its end relative to its start, g(a_after).d / g(a_before).d.
class EnergyLog final : public InnerOptimizer {
 public:
  explicit EnergyLog(InnerOptimizer& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  std::string settings() const override { return inner_.settings(); }
  void begin_step(StepProblem& p, const VecX& a, double value, const VecX& g) override {
    values = {value};
    inner_.begin_step(p, a, value, g);
  }
  std::optional<SolveStatus> iterate(StepProblem& p, VecX& a, double& value, VecX& g) override {
    const VecX a_before = a, g_before = g;
    const auto status = inner_.iterate(p, a, value, g);
    values.push_back(value);
    const VecX d = a - a_before;
    if (d.norm() > 0.0) slope_ratios.push_back(g.dot(d) / g_before.dot(d));
    return status;
  }
  std::vector<double> values;
  std::vector<double> slope_ratios;  // of the iterations that moved a

 private:
  InnerOptimizer& inner_;
};

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
    if (safeguard) EXPECT_EQ(rises, 0);
    else EXPECT_GT(rises, 0) << "the test model must make bad updates for this test to mean anything";
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
    EXPECT_EQ(learned.name(), line_search ? "fnopt-ls" : "fnopt");
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

TEST(LearnedOptimizer, RejectsMissingAndIncompatibleModelFiles) {
  EXPECT_THROW(LearnedOptimizer("/nonexistent/model.pt"), Error);
  const auto path = (std::filesystem::temp_directory_path() / "fnopt_test_wrong_model.pt").string();
  save_fno(path, FNO2d(FNO2dOptions().in_channels(5).width(4).fourier_layers(2).lifting_channels(4).projection_channels(4)));
  try {
    LearnedOptimizer optimizer(path);
    FAIL() << "a 5-channel FNO was accepted";
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
