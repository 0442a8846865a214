#include <fnopt/metrics/obstacle_distance.hpp>

#include <algorithm>
#include <limits>

namespace fnopt {

double min_obstacle_distance(const std::vector<Obstacle>& obstacles, const VecX& positions, double time) {
  double smallest = std::numeric_limits<double>::infinity();
  const Eigen::Index vertices = positions.size() / 3;
  for (const Obstacle& obstacle : obstacles) {
    const Vec3 offset = obstacle.offset(time);
    for (Eigen::Index i = 0; i < vertices; ++i)
      smallest = std::min(smallest, obstacle.distance(positions.segment<3>(3 * i), offset));
  }
  return smallest;
}

double min_obstacle_distance(const Scene& scene, const std::vector<Eigen::VectorXf>& frames) {
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < frames.size(); ++f)
    smallest = std::min(smallest, min_obstacle_distance(scene.obstacles, frames[f].cast<double>(), f * scene.dt));
  return smallest;
}

}  // namespace fnopt
