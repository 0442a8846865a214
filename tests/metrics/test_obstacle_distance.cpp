// min_obstacle_distance: the smallest vertex distance over the frames, each frame's obstacles posed
// at its time, against the distance to a sphere written out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>

namespace fnopt {
namespace {

TEST(ObstacleDistance, SmallestOverVerticesObstaclesAndFramesAtEachFramesPose) {
  Scene scene;
  scene.dt = 0.1;
  scene.obstacles = parse_obstacles("sphere center=0,0,0 radius=0.5 motion=xy_v2; plane point=0,0,-3 normal=0,0,1");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<Eigen::VectorXf> frames;
  double expected = INFINITY;
  for (int f = 0; f < 30; ++f) {
    Eigen::VectorXf x(3 * 20);
    for (int i = 0; i < x.size(); ++i) x[i] = static_cast<float>(u(rng));
    frames.push_back(x);
    const Vec3 centre = scene.obstacles[0].offset(f * scene.dt);  // the sphere's centre at rest is 0
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = x.segment<3>(3 * k).cast<double>();
      expected = std::min({expected, (p - centre).norm() - 0.5, p.z() + 3.0});
    }
  }
  EXPECT_NEAR(min_obstacle_distance(scene, frames), expected, 1e-12);
  EXPECT_EQ(min_obstacle_distance(Scene{}, frames), INFINITY);
}

}  // namespace
}  // namespace fnopt
