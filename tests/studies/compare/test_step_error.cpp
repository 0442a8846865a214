// The per-step error (docs/design.md §8) on a small Newton rollout, and whether Newton's step ends
// at a minimum or a saddle of L.
#include <gtest/gtest.h>

#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/studies/compare/step_error.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

// The Newton reference rollout of a square scene, as the bench reads it.
TrajectoryFrames newton_reference(const Scene& scene) {
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult rollout = run_rollout(resolve(scene), newton, options);
  TrajectoryFrames reference;
  reference.rows = scene.rows;
  reference.cols = scene.cols;
  reference.times = rollout.times;
  reference.positions = rollout.positions;
  return reference;
}

TEST(StepError, IsZeroForNewtonAndBetweenZeroAndOneForAFewGdIterations) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 12;
  const TrajectoryFrames reference = newton_reference(scene);
  StepErrorBench bench(scene, reference, 4);
  EXPECT_EQ(bench.steps().size(), 4u);

  NewtonOptimizer again;
  const StepErrorSummary exact = bench.evaluate(again, NewtonOptimizer::reference_solve_options());
  // Zero to the reference's stop (0.1 m/s^2: ~1e-6 here); a method's per-step error is 1e-2 and up.
  EXPECT_NEAR(exact.mean, 0.0, 1e-5);
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

// Where Newton's step ends: a minimum of L while the cloth hangs from its corners, a saddle while
// the handles squeeze it flat (xz_v2 keeps it in its plane, unbuckled: docs/design.md §6).
TEST(StepError, SaysWhereNewtonsStepEndsAtASaddle) {
  auto saddles = [](const std::string& motion, int frames) {
    Scene scene;
    scene.rows = scene.cols = 12;
    scene.frames = frames;
    scene.motion = motion;
    StepErrorBench bench(scene, newton_reference(scene), 6, /*count_negative_eigenvalues=*/true);
    NewtonOptimizer again;
    const StepErrorSummary summary = bench.evaluate(again, NewtonOptimizer::reference_solve_options());
    return summary.newton_saddles();
  };
  EXPECT_EQ(saddles("xy_v2", 12), 0);
  EXPECT_GE(saddles("xz_v2", 60), 2);  // xz_v2 compresses the cloth: its later samples are saddles
}

// Each sampled state is solved as a Newton started afresh on it would: a factor carried over from
// the previous, unrelated state changes the solve (at 128^2 it sent Newton to other stationary
// points in hundreds of iterations), so the bench must not carry one.
TEST(StepError, NewtonSolvesEverySampledStateAfresh) {
  Scene scene;
  scene.rows = scene.cols = 12;
  scene.frames = 60;
  scene.motion = "xz_v2";
  StepErrorBench bench(scene, newton_reference(scene), 6);
  NewtonParams fresh;
  fresh.reuse_factor_across_steps = false;
  NewtonOptimizer afresh(fresh), carrying;
  const StepErrorSummary exact = bench.evaluate(afresh, NewtonOptimizer::reference_solve_options());
  const StepErrorSummary carried = bench.evaluate(carrying, NewtonOptimizer::reference_solve_options());
  bool carrying_differs = false;
  for (std::size_t k = 0; k < exact.samples.size(); ++k) {
    EXPECT_EQ(exact.samples[k].method_value, exact.samples[k].newton_value) << "sample " << k;
    carrying_differs |= carried.samples[k].method_value != carried.samples[k].newton_value;
  }
  EXPECT_TRUE(carrying_differs) << "a carried factor should change some solve (else this test says nothing)";
}

}  // namespace
}  // namespace fnopt
