#include <fnopt/metrics/chamfer.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include <fnopt/metrics/kd_tree.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// splitmix64: a tiny, platform-independent generator (std::uniform_real_distribution is not
// specified bit for bit, and the sample points must not change with the standard library).
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)

 private:
  std::uint64_t state_;
};

// Mean over `queries` of the squared distance to the nearest point of `tree`.
double mean_nearest_squared(const KdTree3& tree, const std::vector<Vec3>& queries) {
  double sum = 0.0;
  const int n = static_cast<int>(queries.size());
#pragma omp parallel for reduction(+ : sum) schedule(static)
  for (int k = 0; k < n; ++k) sum += tree.nearest(queries[k]).squared_distance;
  return n > 0 ? sum / n : 0.0;
}

bool all_finite(const std::vector<Vec3>& points) {
  return std::all_of(points.begin(), points.end(), [](const Vec3& p) { return p.allFinite(); });
}

}  // namespace

void ChamferOptions::validate() const {
  require(samples >= 1 && samples <= 10'000'000, "cd-samples", "must lie in [1, 10^7]");
}

std::vector<SurfacePoint> sample_surface_points(const VecX& positions, const Triangles& triangles, int count,
                                                std::uint64_t seed) {
  std::vector<SurfacePoint> points;
  const Eigen::Index faces = triangles.rows();
  if (faces == 0 || count <= 0) return points;
  std::vector<double> cumulative(faces);
  double total = 0.0;
  for (Eigen::Index f = 0; f < faces; ++f) {
    const Vec3 a = positions.segment<3>(3 * triangles(f, 0));
    const Vec3 b = positions.segment<3>(3 * triangles(f, 1));
    const Vec3 c = positions.segment<3>(3 * triangles(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    total += std::isfinite(area) ? area : 0.0;
    cumulative[f] = total;
  }
  const bool by_area = total > 0.0;
  SplitMix64 random(seed);
  points.reserve(count);
  for (int k = 0; k < count; ++k) {
    const double u = random.uniform(), r1 = random.uniform(), r2 = random.uniform();
    Eigen::Index f = 0;
    if (by_area) {
      f = std::upper_bound(cumulative.begin(), cumulative.end(), u * total) - cumulative.begin();
      f = std::min<Eigen::Index>(f, faces - 1);
    } else {
      f = std::min<Eigen::Index>(static_cast<Eigen::Index>(u * faces), faces - 1);
    }
    const double root = std::sqrt(r1);
    points.push_back({f, Vec3(1.0 - root, root * (1.0 - r2), root * r2)});
  }
  return points;
}

std::vector<Vec3> surface_point_positions(const VecX& positions, const Triangles& triangles,
                                          const std::vector<SurfacePoint>& points) {
  std::vector<Vec3> result;
  result.reserve(points.size());
  for (const SurfacePoint& p : points)
    result.push_back(p.weights[0] * positions.segment<3>(3 * triangles(p.face, 0)) +
                     p.weights[1] * positions.segment<3>(3 * triangles(p.face, 1)) +
                     p.weights[2] * positions.segment<3>(3 * triangles(p.face, 2)));
  return result;
}

std::vector<Vec3> sample_mesh_surface(const VecX& positions, const Triangles& triangles, int count,
                                      std::uint64_t seed) {
  return surface_point_positions(positions, triangles, sample_surface_points(positions, triangles, count, seed));
}

double chamfer_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.empty() && b.empty()) return 0.0;
  if (a.empty() || b.empty() || !all_finite(a) || !all_finite(b)) return std::nan("");
  const KdTree3 tree_a(a), tree_b(b);
  return mean_nearest_squared(tree_b, a) + mean_nearest_squared(tree_a, b);
}

double mesh_chamfer_distance(const VecX& positions_a, const Triangles& triangles_a, const VecX& positions_b,
                             const Triangles& triangles_b, const ChamferOptions& options) {
  options.validate();
  return chamfer_distance(sample_mesh_surface(positions_a, triangles_a, options.samples, options.seed),
                          sample_mesh_surface(positions_b, triangles_b, options.samples, options.seed));
}

}  // namespace fnopt
