#include <fnopt/metrics/surface_distance.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/io/obj_mesh.hpp>

namespace fnopt {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

template <std::size_t N>
Box box_of(const std::vector<Vec3>& points, const std::array<int, N>& primitive) {
  Box box;
  for (const int v : primitive) box.add(points[v]);
  return box;
}

template <std::size_t N>
void place_tree(BoxTree& tree, const std::vector<Vec3>& points, const std::vector<std::array<int, N>>& primitives) {
  std::vector<Box> boxes(primitives.size());
  for (std::size_t k = 0; k < primitives.size(); ++k) boxes[k] = box_of(points, primitives[k]);
  if (tree.size() == 0)
    tree.build(boxes);
  else
    tree.refit(boxes);
}

// The smallest squared distance from a vertex of `from` to a triangle of `to`, or `best` where that
// is smaller; with `disjoint` (from and to the same surface) a triangle holding the vertex is
// skipped. Each thread's searches start from the smallest value it has found.
double vertices_to_triangles(const DistanceSurface& from, const DistanceSurface& to, bool disjoint,
                             const double best) {
  double smallest = best;
  const int count = static_cast<int>(from.vertices.size());
#pragma omp parallel for reduction(min : smallest) schedule(dynamic, 256)
  for (int k = 0; k < count; ++k) {
    const int v = from.vertices[k];
    const Vec3& p = from.points[v];
    Box point;
    point.add(p);
    auto bound = [&](const Box& box) { return box.squared_distance(point); };
    auto distance = [&](int t) {
      const std::array<int, 3>& f = to.triangles[t];
      if (disjoint && (f[0] == v || f[1] == v || f[2] == v)) return kInfinity;
      return ccd_distance::point_triangle_squared(p, to.points[f[0]], to.points[f[1]], to.points[f[2]]);
    };
    smallest = to.triangle_tree.nearest(bound, distance, std::min(smallest, best));
  }
  return smallest;
}

// The same for the edges of `from` and the edges of `to`; with `disjoint`, edges sharing a vertex
// are skipped.
double edges_to_edges(const DistanceSurface& from, const DistanceSurface& to, bool disjoint, const double best) {
  double smallest = best;
  const int count = static_cast<int>(from.edges.size());
#pragma omp parallel for reduction(min : smallest) schedule(dynamic, 256)
  for (int k = 0; k < count; ++k) {
    const std::array<int, 2>& a = from.edges[k];
    const Box segment = box_of(from.points, a);
    auto bound = [&](const Box& box) { return box.squared_distance(segment); };
    auto distance = [&](int e) {
      const std::array<int, 2>& b = to.edges[e];
      if (disjoint && (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])) return kInfinity;
      return ccd_distance::segment_segment_squared(from.points[a[0]], from.points[a[1]], to.points[b[0]],
                                                   to.points[b[1]]);
    };
    smallest = to.edge_tree.nearest(bound, distance, std::min(smallest, best));
  }
  return smallest;
}

}  // namespace

void DistanceSurface::set_triangles(std::vector<std::array<int, 3>> faces) {
  triangles = std::move(faces);
  edges = unique_edges(triangles);
  // The points on a triangle are the edges' ends: a point on none is not on the surface.
  vertices.clear();
  for (const auto& e : edges) vertices.insert(vertices.end(), e.begin(), e.end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  triangle_tree = BoxTree();
  edge_tree = BoxTree();
}

void DistanceSurface::set_grid(int rows, int cols) {
  const auto faces = Grid{rows, cols, 1.0}.triangles();
  std::vector<std::array<int, 3>> list(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) list[f] = {faces(f, 0), faces(f, 1), faces(f, 2)};
  set_triangles(std::move(list));
}

void DistanceSurface::place() {
  place_tree(triangle_tree, points, triangles);
  place_tree(edge_tree, points, edges);
}

double surface_distance(const DistanceSurface& a, const DistanceSurface& b) {
  double best = vertices_to_triangles(a, b, false, kInfinity);
  best = vertices_to_triangles(b, a, false, best);
  return std::sqrt(edges_to_edges(a, b, false, best));
}

double disjoint_self_distance(const DistanceSurface& surface) {
  const double best = vertices_to_triangles(surface, surface, true, kInfinity);
  return std::sqrt(edges_to_edges(surface, surface, true, best));
}

}  // namespace fnopt
