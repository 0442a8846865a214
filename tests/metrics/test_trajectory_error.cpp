// e_3D against a hand computation and a comparison of trajectories across frame rates and
// resolutions (docs/design.md §8).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/metrics/trajectory_error.hpp>

namespace fnopt {
namespace {

TEST(TrajectoryError, RelativeFrameErrorMatchesAHandComputation) {
  Eigen::VectorXf reference(6), x(6);
  reference << 1, 2, 2, 0, 0, 0;  // norm 3
  x << 1, 2, 2, 0, 0, 1.5;        // differs by 1.5 in one coordinate
  EXPECT_NEAR(relative_frame_error(x, reference), 0.5, 1e-7);

  // Two frames: errors 0 and 0.5, mean 0.25.
  TrajectoryFrames ref, roll;
  ref.rows = roll.rows = 1;
  ref.cols = roll.cols = 2;
  ref.times = roll.times = {0.0, 0.1};
  ref.positions = {reference, reference};
  roll.positions = {reference, x};
  TrajectoryComparisonOptions options;
  options.chamfer_enabled = false;
  const TrajectoryComparison c = compare_trajectories(ref, roll, -1.0, options);
  ASSERT_EQ(c.matches.size(), 2u);
  EXPECT_TRUE(c.correspondence);
  EXPECT_NEAR(c.e3d, 0.25, 1e-7);
}

TrajectoryFrames trajectory(const Grid& grid, int frames, double dt, double drift) {
  TrajectoryFrames t;
  t.rows = grid.rows;
  t.cols = grid.cols;
  for (int k = 0; k < frames; ++k) {
    VecX x = grid.rest_positions();
    for (int v = 0; v < grid.vertex_count(); ++v) x[3 * v + 1] -= drift * k;  // along the normal
    t.times.push_back(k * dt);
    t.positions.push_back(x.cast<float>());
  }
  return t;
}

TEST(TrajectoryError, ComparesAcrossRatesAndResolutions) {
  const Grid g32 = Grid::make(9, 9, 1.0), g16 = Grid::make(5, 5, 1.0);
  const TrajectoryFrames reference = trajectory(g32, 20, 1.0 / 30.0, 0.0);
  const TrajectoryFrames rollout = trajectory(g16, 39, 1.0 / 60.0, 0.001);  // moves 1 mm per step
  const TrajectoryComparison c = compare_trajectories(reference, rollout, g16.spacing);
  EXPECT_EQ(c.matches.size(), 20u);
  EXPECT_FALSE(c.correspondence);
  EXPECT_TRUE(std::isnan(c.e3d));
  // Frame k (t = k/30) of the rollout moved 2k mm along the normal: CD ~ 2 (2k mm)^2 plus the sampling floor.
  double expected = 0.0;
  for (int k = 0; k < 20; ++k) expected += 2 * std::pow(0.002 * k, 2) / 20;
  EXPECT_NEAR(c.chamfer, expected, 0.1 * expected + 1.5e-4);
  EXPECT_NEAR(c.max_strain, 0.0, 1e-6);
  EXPECT_NE(c.describe_matching().find("20 of 20"), std::string::npos);
}

}  // namespace
}  // namespace fnopt
