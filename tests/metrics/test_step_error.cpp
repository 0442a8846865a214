// The per-step error (docs/design.md §8) on a small Newton rollout.
#include <gtest/gtest.h>

#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/metrics/step_error.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

TEST(StepError, IsZeroForNewtonAndBetweenZeroAndOneForAFewGdIterations) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 12;
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult rollout = run_rollout(resolve(scene), newton, options);
  TrajectoryFrames reference;
  reference.rows = reference.cols = 8;
  reference.times = rollout.times;
  reference.positions = rollout.positions;
  StepErrorBench bench(scene, reference, 4);
  EXPECT_EQ(bench.steps().size(), 4u);

  NewtonOptimizer again;
  const StepErrorSummary exact = bench.evaluate(again, NewtonOptimizer::reference_solve_options());
  EXPECT_NEAR(exact.mean, 0.0, 1e-6);
  GradientDescentOptimizer gd;
  const StepErrorSummary rough = bench.evaluate(gd, {3, 0.0});
  for (const auto& sample : rough.samples) {
    EXPECT_GT(sample.error, 0.0);
    EXPECT_LT(sample.error, 1.0);
  }
  // A reference without a frame every step is refused.
  TrajectoryFrames sparse = reference;
  for (double& t : sparse.times) t *= 2;
  EXPECT_ANY_THROW(StepErrorBench(scene, sparse, 4));
}

}  // namespace
}  // namespace fnopt
