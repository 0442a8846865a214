// A training environment lives --env-lifetime time steps, then the next generation (new
// material, pose, handles and motion) replaces it; its material comes from the pool's ranges; a
// step scale stuck at its floor starts the next time step afresh.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/training/training_env.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

PoolOptions one_iteration_per_step(int lifetime) {
  PoolOptions pool;
  pool.resolutions = {8};
  pool.environments = 1;
  pool.max_age = lifetime;
  pool.budgets = {1};
  return pool;
}

TEST(TrainingEnv, IsRenewedAfterItsLifetime) {
  // a = 0 keeps the cloth still, so nothing but age can renew it.
  TrainingEnv env(one_iteration_per_step(3), 7, 0);
  for (int step = 0; step < 3; ++step) {
    EXPECT_EQ(env.generation(), 0) << "time step " << step;
    EXPECT_TRUE(env.finish_iteration());
  }
  EXPECT_EQ(env.generation(), 1);
  for (int step = 0; step < 3; ++step) env.finish_iteration();
  EXPECT_EQ(env.generation(), 2);
}

TEST(TrainingEnv, AStepScaleAtItsFloorStartsTheNextTimeStepAfresh) {
  PoolOptions pool = one_iteration_per_step(10);
  pool.budgets = {2};
  TrainingEnv env(pool, 7, 0);
  // Coordinate x at the floor, y just above it, z at a working scale.
  env.scale = torch::tensor({kMinStepScale, 2 * kMinStepScale, 0.01}).view({3, 1, 1, 1});
  const torch::Tensor before = env.scale.clone();
  EXPECT_FALSE(env.finish_iteration());
  EXPECT_TRUE(torch::equal(env.scale, before)) << "within a time step the scale is the network's";
  EXPECT_TRUE(env.finish_iteration());
  EXPECT_EQ(env.generation(), 0);
  EXPECT_FLOAT_EQ(env.scale[0].item<float>(), static_cast<float>(kInitialStepScale));
  EXPECT_FLOAT_EQ(env.scale[1].item<float>(), static_cast<float>(2 * kMinStepScale));
  EXPECT_FLOAT_EQ(env.scale[2].item<float>(), 0.01f);
}

// Takes `count` proposals of -t g by the environment's rule.
void take_scaled_gradients(TrainingEnv& env, int count) {
  for (int i = 0; i < count; ++i) {
    StepProblem problem(env.objective(), env.dirichlet());
    VecX gradient;
    double value = problem.value_gradient(env.acceleration(), gradient);
    const double unit = acceleration_per_grid_unit(env.grid(), env.dt());
    const double t = 0.3 * unit / gradient.lpNorm<Eigen::Infinity>();
    const torch::Tensor g = to_coordinate_samples(gradient, env.grid());
    env.rule().apply(problem, g, {to_coordinate_samples(gradient, env.grid(), -t / unit), env.scale},
                     env.acceleration(), value, gradient);
    env.finish_iteration();
  }
}

TEST(TrainingEnv, KeepsItsProposalsAcrossTimeStepsAndForgetsThemWhenRenewed) {
  PoolOptions pool = one_iteration_per_step(4);
  pool.subspace = 3;
  TrainingEnv env(pool, 7, 0);
  take_scaled_gradients(env, 2);  // two time steps of one proposal each
  EXPECT_EQ(env.generation(), 0);
  EXPECT_EQ(env.rule().pairs().size(), 2);

  // A checkpoint restores the same pairs, oldest first.
  const auto restored = TrainingEnv::restored(pool, 7, 0, env.state_tensors());
  ASSERT_EQ(restored->rule().pairs().size(), 2);
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(restored->rule().pairs().s(j), env.rule().pairs().s(j)) << j;
    EXPECT_EQ(restored->rule().pairs().y(j), env.rule().pairs().y(j)) << j;
  }

  take_scaled_gradients(env, 2);  // the lifetime ends: a new cloth, no pairs from the old one
  EXPECT_EQ(env.generation(), 1);
  EXPECT_EQ(env.rule().pairs().size(), 0);
  take_scaled_gradients(env, 1);
  EXPECT_EQ(env.rule().pairs().size(), 1);
}

TEST(TrainingEnv, TakesProposalsAsTheyAreWithoutASubspace) {
  TrainingEnv env(one_iteration_per_step(4), 7, 0);
  take_scaled_gradients(env, 2);
  EXPECT_EQ(env.rule().pairs().size(), 0);
  EXPECT_FALSE(env.rule().params().safeguard);
  EXPECT_EQ(env.state_tensors().size(), static_cast<std::size_t>(TrainingEnv::kStateTensors));
}

// pqn's K iterations as the reference: the same environment (same seed, id and generation) with
// an L* between Newton's exact minimum and the start, closer to Newton's as K grows; the
// Newton reference of the same step is the lowest.
TEST(TrainingEnv, APqnReferenceBoundsNewtonsFromAboveAndApproachesIt) {
  PoolOptions pool;
  pool.resolutions = {12};
  pool.environments = 3;
  for (int id = 0; id < pool.environments; ++id) {
    const TrainingEnv newton(pool, 5, id);
    double previous_gap = INFINITY;
    for (const int iterations : {3, 10, 40}) {
      PoolOptions with_pqn = pool;
      with_pqn.reference_pqn_iterations = iterations;
      const TrainingEnv env(with_pqn, 5, id);
      ASSERT_EQ(env.initial_loss(), newton.initial_loss()) << "the same environment";
      const double start = newton.initial_loss() - newton.reference_loss();
      const double gap = (env.reference_loss() - newton.reference_loss()) / start;
      EXPECT_GE(gap, -1e-9) << "id " << id << ", K = " << iterations;
      EXPECT_LT(gap, 1.0) << "id " << id << ", K = " << iterations;
      EXPECT_LE(gap, previous_gap + 1e-12) << "id " << id << ", K = " << iterations;
      if (iterations == 3) {
        EXPECT_GT(gap, 1e-4) << "id " << id << ": 3 pqn iterations are not Newton's step";
      }
      previous_gap = gap;
    }
    EXPECT_LT(previous_gap, 0.05) << "id " << id << ": 40 pqn iterations land near Newton's step";
  }
  pool.reference_pqn_iterations = -1;
  EXPECT_THROW(pool.validate(), Error);
}

TEST(TrainingEnv, RejectsALifetimeBelowOneStep) {
  EXPECT_THROW(one_iteration_per_step(0).validate(), Error);
  EXPECT_NO_THROW(one_iteration_per_step(1).validate());
}

TEST(TrainingRanges, SetsAQuantityByNameAndRejectsOthers) {
  TrainingRanges r;
  r.set("shear", 0.5, 200.0);
  EXPECT_EQ(r.shear_min, 0.5);
  EXPECT_EQ(r.shear_max, 200.0);
  EXPECT_EQ(r.stretch_min, TrainingRanges{}.stretch_min);
  EXPECT_THROW(r.set("speed", 1.0, 2.0), Error);
  r.set("damping", 0.3, 0.005);
  EXPECT_THROW(r.validate(), Error);
  EXPECT_NE(r.text().find("shear 0.5:200"), std::string::npos) << r.text();
}

// One-point ranges pin the material: every environment of every generation gets exactly those
// grid-unit values, damped or not as the undamped share says.
TEST(TrainingEnv, SamplesItsMaterialFromThePoolRanges) {
  for (const double undamped_share : {0.0, 1.0}) {
    PoolOptions pool = one_iteration_per_step(1);
    pool.environments = 3;
    pool.ranges.set("stretch", 150.0, 150.0);
    pool.ranges.set("shear", 7.0, 7.0);
    pool.ranges.set("bend", 0.5, 0.5);
    pool.ranges.set("gravity", 0.1, 0.1);
    pool.ranges.set("damping", 0.02, 0.02);
    pool.ranges.undamped_share = undamped_share;
    for (int id = 0; id < pool.environments; ++id)
      for (long generation : {0L, 5L}) {
        TrainingEnv env(pool, 3, id, generation);
        const BackwardEulerObjective& objective = env.objective();
        const GridUnitStiffness k =
            grid_unit_stiffness(env.grid(), objective.material(), env.dt(), objective.gravity().norm());
        EXPECT_NEAR(k.stretch, 150.0, 1e-9);
        EXPECT_NEAR(k.shear, 7.0, 1e-11);
        EXPECT_NEAR(k.bend, 0.5, 1e-12);
        EXPECT_NEAR(k.gravity, 0.1, 1e-12);
        EXPECT_NEAR(objective.material().damping * env.dt(), undamped_share == 1.0 ? 0.0 : 0.02, 1e-12);
      }
  }
}

}  // namespace
}  // namespace fnopt
