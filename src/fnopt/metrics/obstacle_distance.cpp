#include <fnopt/metrics/obstacle_distance.hpp>

#include <algorithm>
#include <limits>
#include <string>
#include <utility>

#include <fnopt/metrics/surface_distance.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// The distances of a rows x cols cloth to the mesh obstacles among `obstacles`, state after state:
// the primitives are listed and the trees built once.
class MeshDistances {
 public:
  MeshDistances(const std::vector<Obstacle>& obstacles, int rows, int cols);
  // The smallest distance of the cloth at `positions` to a mesh posed at `time`; +inf without one.
  double at(const VecX& positions, double time);

 private:
  int rows_, cols_;
  DistanceSurface cloth_;
  std::vector<std::pair<const Obstacle*, DistanceSurface>> meshes_;
};

MeshDistances::MeshDistances(const std::vector<Obstacle>& obstacles, int rows, int cols) : rows_(rows), cols_(cols) {
  for (const Obstacle& obstacle : obstacles) {
    if (!obstacle.is_mesh()) continue;
    DistanceSurface mesh;
    mesh.set_triangles(obstacle.mesh()->triangles());
    meshes_.emplace_back(&obstacle, std::move(mesh));
  }
  if (meshes_.empty()) return;
  cloth_.set_grid(rows, cols);
}

double MeshDistances::at(const VecX& positions, double time) {
  if (meshes_.empty()) return std::numeric_limits<double>::infinity();
  require(positions.size() == 3 * Eigen::Index{rows_} * cols_, "positions",
          "holds " + std::to_string(positions.size()) + " values, a grid of " + std::to_string(rows_) + " x " +
              std::to_string(cols_) + " vertices needs 3 per vertex");
  cloth_.points.resize(rows_ * cols_);
  for (int v = 0; v < rows_ * cols_; ++v) cloth_.points[v] = positions.segment<3>(3 * v);
  cloth_.place();
  double smallest = std::numeric_limits<double>::infinity();
  for (auto& [obstacle, mesh] : meshes_) {
    obstacle->mesh_vertices(time, mesh.points);
    mesh.place();
    smallest = std::min(smallest, surface_distance(cloth_, mesh));
  }
  return smallest;
}

// The smallest signed distance of the vertices to the analytic obstacles at `time`.
double analytic_distance(const std::vector<Obstacle>& obstacles, const VecX& positions, double time) {
  double smallest = std::numeric_limits<double>::infinity();
  const Eigen::Index vertices = positions.size() / 3;
  for (const Obstacle& obstacle : obstacles) {
    if (obstacle.is_mesh()) continue;
    const Vec3 offset = obstacle.offset(time);
    for (Eigen::Index i = 0; i < vertices; ++i)
      smallest = std::min(smallest, obstacle.distance(positions.segment<3>(3 * i), offset));
  }
  return smallest;
}

}  // namespace

double min_obstacle_distance(const std::vector<Obstacle>& obstacles, const VecX& positions, int rows, int cols,
                             double time) {
  MeshDistances meshes(obstacles, rows, cols);
  return std::min(analytic_distance(obstacles, positions, time), meshes.at(positions, time));
}

double min_obstacle_distance(const Scene& scene, const std::vector<Eigen::VectorXf>& frames) {
  MeshDistances meshes(scene.obstacles, scene.rows, scene.cols);
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const VecX x = frames[f].cast<double>();
    smallest = std::min({smallest, analytic_distance(scene.obstacles, x, f * scene.dt), meshes.at(x, f * scene.dt)});
  }
  return smallest;
}

}  // namespace fnopt
