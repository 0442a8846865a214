// The rollout loop: Newton finishes a short benchmark rollout with every step converged and
// handles on their trajectory; a diverging optimizer is detected, stopped and reported.
#include <gtest/gtest.h>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

Scene small_scene() {
  Scene scene;
  scene.rows = scene.cols = 10;
  scene.frames = 40;
  return scene;
}

// Four Newton iterations per step reach 1e-9 on some steps of this scene and not on others
// (24 of 40): converged_steps() counts exactly the steps whose status says so.
TEST(Rollout, CountsTheConvergedSteps) {
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = {4, 1e-9};
  const RolloutResult r = run_rollout(resolve(small_scene()), newton, options);
  int converged = 0;
  for (const auto& s : r.steps) converged += is_converged(s.status);
  EXPECT_EQ(r.converged_steps(), converged);
  EXPECT_GT(converged, 0);
  EXPECT_LT(converged, static_cast<int>(r.steps.size()));
}

TEST(Rollout, NewtonConvergesEveryStepAndHandlesFollowTheirTargets) {
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult r = run_rollout(resolve(small_scene()), newton, options);
  ASSERT_FALSE(r.diverged) << r.divergence;
  ASSERT_EQ(r.steps.size(), 40u);
  ASSERT_EQ(r.positions.size(), 41u);
  for (const auto& s : r.steps) EXPECT_TRUE(is_converged(s.status)) << to_string(s.status);
  EXPECT_EQ(r.converged_steps(), 40);
  for (std::size_t t = 0; t < r.positions.size(); ++t)
    for (std::size_t h = 0; h < r.handle_vertices.size(); ++h)
      EXPECT_LT((r.positions[t].segment<3>(3 * r.handle_vertices[h]).cast<double>() - r.handle_targets[t][h]).norm(),
                1e-5);
  EXPECT_GT(r.max_strain(), 0.0);
  EXPECT_LT(r.max_strain(), 0.5);
}

// Doubles the acceleration's free part every iteration: an optimizer that blows up.
class Exploding final : public InnerOptimizer {
 public:
  std::string name() const override { return "exploding"; }
  std::string settings() const override { return ""; }
  void begin_step(StepProblem&, const VecX&, double, const VecX&) override {}
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    a -= 1e6 * gradient;
    value = problem.value_gradient(a, gradient);
    return std::nullopt;
  }
};

TEST(Rollout, DivergenceIsDetectedStoppedAndExplained) {
  Exploding exploding;
  RolloutOptions options;
  options.solve = {5, 0.0};
  const RolloutResult r = run_rollout(resolve(small_scene()), exploding, options);
  EXPECT_TRUE(r.diverged);
  EXPECT_NE(r.divergence.find("diverged at step"), std::string::npos) << r.divergence;
  EXPECT_LT(r.steps.size(), 40u);
  for (const auto& x : r.positions) EXPECT_TRUE(x.allFinite());  // nothing non-finite is kept
}

}  // namespace
}  // namespace fnopt
