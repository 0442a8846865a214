// The k-d tree of the error metrics (docs/design.md §8) against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include <fnopt/metrics/kd_tree.hpp>

namespace fnopt {
namespace {

std::vector<Vec3> random_points(int n, unsigned seed, double scale = 1.0) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-scale, scale);
  std::vector<Vec3> points(n);
  for (auto& p : points) p = Vec3(uniform(random), uniform(random), uniform(random));
  return points;
}

TEST(KdTree3, NearestNeighbourEqualsBruteForce) {
  std::vector<Vec3> points = random_points(2000, 1);
  points.push_back(points[5]);                                             // a duplicate
  for (int k = 0; k < 50; ++k) points.push_back(Vec3(0.5, 0.25, -0.125));  // many equal points
  const KdTree3 tree(points);
  for (const Vec3& q : random_points(1000, 2, 1.3)) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) best = std::min(best, (p - q).squaredNorm());
    const auto found = tree.nearest(q);
    ASSERT_GE(found.index, 0);
    EXPECT_EQ(found.squared_distance, best);
    EXPECT_EQ((points[found.index] - q).squaredNorm(), best);
  }
  EXPECT_EQ(KdTree3({}).nearest(Vec3::Zero()).index, -1);
}

}  // namespace
}  // namespace fnopt
