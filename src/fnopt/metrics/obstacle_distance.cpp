#include <fnopt/metrics/obstacle_distance.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/box_tree.hpp>
#include <fnopt/io/obj_mesh.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

using Face = std::array<int, 3>;
using Edge = std::array<int, 2>;

// One side of a cloth-mesh pair: its points, the triangles and edges on them, the points on some
// triangle (the surface's vertices), and box trees over its triangles and its edges.
struct Surface {
  std::vector<Vec3> points;
  std::vector<Face> triangles;
  std::vector<Edge> edges;
  std::vector<int> vertices;
  BoxTree triangle_tree, edge_tree;
};

template <std::size_t N>
Box box_of(const std::vector<Vec3>& points, const std::array<int, N>& primitive) {
  Box box;
  for (const int v : primitive) box.add(points[v]);
  return box;
}

// Builds `tree` over the primitives' boxes the first time, then refits it: the grid's triangles
// stay neighbours however the cloth moves, and a mesh keeps its triangles, so the tree built on
// the first state stays tight enough (and every search exact) without a rebuild per state.
template <std::size_t N>
void place(BoxTree& tree, const std::vector<Vec3>& points, const std::vector<std::array<int, N>>& primitives) {
  std::vector<Box> boxes(primitives.size());
  for (std::size_t k = 0; k < primitives.size(); ++k) boxes[k] = box_of(points, primitives[k]);
  if (tree.size() == 0)
    tree.build(boxes);
  else
    tree.refit(boxes);
}

// The smallest squared distance from a vertex of `from` to a triangle of `to`, or `best` where
// that is smaller. Each thread's searches start from the smallest value it has found and `best`.
double vertices_to_triangles(const Surface& from, const Surface& to, const double best) {
  double smallest = best;
  const int count = static_cast<int>(from.vertices.size());
#pragma omp parallel for reduction(min : smallest) schedule(dynamic, 256)
  for (int k = 0; k < count; ++k) {
    const Vec3& p = from.points[from.vertices[k]];
    Box point;
    point.add(p);
    auto bound = [&](const Box& box) { return box.squared_distance(point); };
    auto distance = [&](int t) {
      const Face& f = to.triangles[t];
      return ccd_distance::point_triangle_squared(p, to.points[f[0]], to.points[f[1]], to.points[f[2]]);
    };
    smallest = to.triangle_tree.nearest(bound, distance, std::min(smallest, best));
  }
  return smallest;
}

// The same for the edges of `from` and the edges of `to`.
double edges_to_edges(const Surface& from, const Surface& to, const double best) {
  double smallest = best;
  const int count = static_cast<int>(from.edges.size());
#pragma omp parallel for reduction(min : smallest) schedule(dynamic, 256)
  for (int k = 0; k < count; ++k) {
    const Edge& a = from.edges[k];
    const Box segment = box_of(from.points, a);
    auto bound = [&](const Box& box) { return box.squared_distance(segment); };
    auto distance = [&](int e) {
      const Edge& b = to.edges[e];
      return ccd_distance::segment_segment_squared(from.points[a[0]], from.points[a[1]], to.points[b[0]],
                                                   to.points[b[1]]);
    };
    smallest = to.edge_tree.nearest(bound, distance, std::min(smallest, best));
  }
  return smallest;
}

// The unsigned distance between the two surfaces: the smallest of their vertex-triangle pairs
// both ways and their edge-edge pairs.
double surface_distance(const Surface& cloth, const Surface& mesh) {
  double best = vertices_to_triangles(cloth, mesh, std::numeric_limits<double>::infinity());
  best = vertices_to_triangles(mesh, cloth, best);
  return std::sqrt(edges_to_edges(cloth, mesh, best));
}

// The distances of a rows x cols cloth to the mesh obstacles among `obstacles`, state after state:
// the primitives are listed and the trees built once.
class MeshDistances {
 public:
  MeshDistances(const std::vector<Obstacle>& obstacles, int rows, int cols);
  // The smallest distance of the cloth at `positions` to a mesh posed at `time`; +inf without one.
  double at(const VecX& positions, double time);

 private:
  int rows_, cols_;
  Surface cloth_;  // every vertex is on a triangle
  std::vector<std::pair<const Obstacle*, Surface>> meshes_;
};

MeshDistances::MeshDistances(const std::vector<Obstacle>& obstacles, int rows, int cols) : rows_(rows), cols_(cols) {
  for (const Obstacle& obstacle : obstacles) {
    if (!obstacle.is_mesh()) continue;
    Surface mesh;
    mesh.triangles = obstacle.mesh()->triangles();
    mesh.edges = obstacle.mesh()->edges();
    // The vertices on a triangle are the edges' ends: a vertex on none is not on the surface.
    for (const Edge& e : mesh.edges) mesh.vertices.insert(mesh.vertices.end(), e.begin(), e.end());
    std::sort(mesh.vertices.begin(), mesh.vertices.end());
    mesh.vertices.erase(std::unique(mesh.vertices.begin(), mesh.vertices.end()), mesh.vertices.end());
    meshes_.emplace_back(&obstacle, std::move(mesh));
  }
  if (meshes_.empty()) return;
  const auto triangles = Grid{rows, cols, 1.0}.triangles();
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
    cloth_.triangles.push_back({triangles(f, 0), triangles(f, 1), triangles(f, 2)});
  cloth_.edges = unique_edges(cloth_.triangles);
  for (int v = 0; v < rows * cols; ++v) cloth_.vertices.push_back(v);
}

double MeshDistances::at(const VecX& positions, double time) {
  if (meshes_.empty()) return std::numeric_limits<double>::infinity();
  require(positions.size() == 3 * Eigen::Index{rows_} * cols_, "positions",
          "holds " + std::to_string(positions.size()) + " values, a grid of " + std::to_string(rows_) + " x " +
              std::to_string(cols_) + " vertices needs 3 per vertex");
  cloth_.points.resize(rows_ * cols_);
  for (int v = 0; v < rows_ * cols_; ++v) cloth_.points[v] = positions.segment<3>(3 * v);
  place(cloth_.triangle_tree, cloth_.points, cloth_.triangles);
  double smallest = std::numeric_limits<double>::infinity();
  for (auto& [obstacle, mesh] : meshes_) {
    obstacle->mesh_vertices(time, mesh.points);
    place(mesh.triangle_tree, mesh.points, mesh.triangles);
    place(mesh.edge_tree, mesh.points, mesh.edges);
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
