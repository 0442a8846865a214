#include <fnopt/metrics/cloth_distance.hpp>

#include <algorithm>
#include <limits>

#include <fnopt/metrics/surface_distance.hpp>

namespace fnopt {

std::vector<double> cloth_distance_per_frame(const TrajectoryFrames& frames) {
  DistanceSurface cloth;
  cloth.set_grid(frames.rows, frames.cols);
  cloth.points.resize(static_cast<std::size_t>(frames.rows) * frames.cols);
  std::vector<double> distances;
  for (const Eigen::VectorXf& x : frames.positions) {
    for (std::size_t v = 0; v < cloth.points.size(); ++v) cloth.points[v] = x.segment<3>(3 * v).cast<double>();
    cloth.place();
    distances.push_back(disjoint_self_distance(cloth));
  }
  return distances;
}

double min_cloth_distance(const TrajectoryFrames& frames) {
  const std::vector<double> distances = cloth_distance_per_frame(frames);
  return distances.empty() ? std::numeric_limits<double>::infinity()
                           : *std::min_element(distances.begin(), distances.end());
}

}  // namespace fnopt
