// The benchmark row: its counts are those of the passes it ran.
#include <gtest/gtest.h>

#include <fnopt/adjoint/adjoint_bench.hpp>

namespace fnopt {
namespace {

TEST(AdjointBench, TheRowCountsTheWorkOfItsPasses) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 11;
  const ResolvedScene resolved = resolve(scene);
  const AdjointBenchRow row = bench_adjoint(resolved);
  EXPECT_EQ(row.rows, 8);
  EXPECT_EQ(row.steps, 10);
  EXPECT_EQ(row.solves, row.steps);
  EXPECT_GE(row.factorizations, row.steps);
  EXPECT_EQ(row.record_bytes, record_rollout(resolved).memory_bytes());
  EXPECT_GT(row.forward_ms_per_frame, 0.0);
  EXPECT_GT(row.backward_ms_per_frame, 0.0);
  EXPECT_TRUE(is_complete(row.status));
}

}  // namespace
}  // namespace fnopt
