// A training environment lives --env-lifetime time steps, then the next generation (new
// material, pose, handles and motion) replaces it.
#include <gtest/gtest.h>

#include "optimizer/learned/training_env.hpp"
#include "util/error.hpp"

namespace fnopt {
namespace {

PoolOptions one_iteration_per_step(int lifetime) {
  PoolOptions pool;
  pool.resolution = 8;
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

TEST(TrainingEnv, RejectsALifetimeBelowOneStep) {
  EXPECT_THROW(one_iteration_per_step(0).validate(), Error);
  EXPECT_NO_THROW(one_iteration_per_step(1).validate());
}

}  // namespace
}  // namespace fnopt
