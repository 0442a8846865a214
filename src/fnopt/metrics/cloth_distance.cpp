#include <fnopt/metrics/cloth_distance.hpp>

#include <algorithm>
#include <limits>

#include <fnopt/metrics/surface_distance.hpp>

namespace fnopt {

double min_cloth_distance(const TrajectoryFrames& frames) {
  DistanceSurface cloth;
  cloth.set_grid(frames.rows, frames.cols);
  cloth.points.resize(static_cast<std::size_t>(frames.rows) * frames.cols);
  double smallest = std::numeric_limits<double>::infinity();
  for (const Eigen::VectorXf& x : frames.positions) {
    for (std::size_t v = 0; v < cloth.points.size(); ++v) cloth.points[v] = x.segment<3>(3 * v).cast<double>();
    cloth.place();
    smallest = std::min(smallest, disjoint_self_distance(cloth));
  }
  return smallest;
}

}  // namespace fnopt
