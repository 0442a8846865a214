#include <fnopt/contact/neighbour_pairs.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace fnopt {
namespace {

struct Topology {
  const Grid& grid;
  const std::vector<std::array<int, 3>>& triangles;
  const std::vector<std::array<int, 2>>& edges;

  int row(int v) const { return v / grid.cols; }
  int col(int v) const { return v % grid.cols; }
  bool near(int u, int w) const { return std::abs(row(u) - row(w)) <= 1 && std::abs(col(u) - col(w)) <= 1; }
  // The first of the two triangles of cell (i, j), as Grid::triangles() numbers them.
  int first_triangle(int i, int j) const { return 2 * (i * (grid.cols - 1) + j); }
  bool cell(int i, int j) const { return i >= 0 && j >= 0 && i < grid.rows - 1 && j < grid.cols - 1; }
  int edge_index(int u, int w) const {
    const std::array<int, 2> e = {std::min(u, w), std::max(u, w)};
    return static_cast<int>(std::lower_bound(edges.begin(), edges.end(), e) - edges.begin());
  }
};

// Among `planes`, the one that separates best at rest.
SeparatingPlane best_plane(const std::vector<SeparatingPlane>& planes, const VecX& rest, const PlaneNormals& normals) {
  double best_separation = -std::numeric_limits<double>::infinity();
  SeparatingPlane best = planes.front();
  for (const SeparatingPlane& plane : planes) {
    const double s = plane.separation(rest, normals);
    if (s > best_separation) best_separation = s, best = plane;
  }
  return best;
}

// The planes that may keep edge `back` behind and edge `front` in front: through `back`,
// perpendicular to each triangle that holds it, and through either end, perpendicular to it.
void edge_planes(const std::array<int, 2>& back, const std::array<int, 2>& front, const Topology& topology,
                 std::vector<SeparatingPlane>& out) {
  const int i0 = std::min(topology.row(back[0]), topology.row(back[1])) - 1;
  const int j0 = std::min(topology.col(back[0]), topology.col(back[1])) - 1;
  for (int i = i0; i <= i0 + 1; ++i)
    for (int j = j0; j <= j0 + 1; ++j) {
      if (!topology.cell(i, j)) continue;
      for (int t = topology.first_triangle(i, j); t < topology.first_triangle(i, j) + 2; ++t)
        for (int k = 0; k < 3; ++k) {
          const auto& tri = topology.triangles[t];
          const int a = tri[k], b = tri[(k + 1) % 3];
          if ((a == back[0] && b == back[1]) || (a == back[1] && b == back[0]))
            out.push_back({SeparatingPlane::Kind::EdgeOfTriangle, t, k, a, front});
        }
    }
  const int e = topology.edge_index(back[0], back[1]);
  const auto& edge = topology.edges[e];
  out.push_back({SeparatingPlane::Kind::AlongEdge, e, 0, edge[1], front});
  out.push_back({SeparatingPlane::Kind::AgainstEdge, e, 0, edge[0], front});
}

void point_triangle_pairs(const Topology& topology, const VecX& rest, const PlaneNormals& normals,
                          std::vector<NeighbourPair>& out) {
  std::vector<SeparatingPlane> planes;
  for (int v = 0; v < topology.grid.vertex_count(); ++v)
    for (int i = topology.row(v) - 2; i <= topology.row(v) + 1; ++i)
      for (int j = topology.col(v) - 2; j <= topology.col(v) + 1; ++j) {
        if (!topology.cell(i, j)) continue;
        for (int t = topology.first_triangle(i, j); t < topology.first_triangle(i, j) + 2; ++t) {
          const auto& tri = topology.triangles[t];
          if (tri[0] == v || tri[1] == v || tri[2] == v) continue;
          if (!topology.near(v, tri[0]) && !topology.near(v, tri[1]) && !topology.near(v, tri[2])) continue;
          planes.clear();
          for (int k = 0; k < 3; ++k) planes.push_back({SeparatingPlane::Kind::EdgeOfTriangle, t, k, tri[k], {v, -1}});
          out.push_back({{SelfContactPair::Kind::PointTriangle, {v, tri[0], tri[1], tri[2]}},
                         best_plane(planes, rest, normals)});
        }
      }
}

void edge_edge_pairs(const Topology& topology, const VecX& rest, const PlaneNormals& normals,
                     std::vector<NeighbourPair>& out) {
  std::vector<int> nearby;
  std::vector<SeparatingPlane> planes;
  for (int e = 0; e < static_cast<int>(topology.edges.size()); ++e) {
    const auto& a = topology.edges[e];
    nearby.clear();
    const int i0 = std::min(topology.row(a[0]), topology.row(a[1]));
    const int j0 = std::min(topology.col(a[0]), topology.col(a[1]));
    for (int i = i0 - 2; i <= i0 + 2; ++i)
      for (int j = j0 - 2; j <= j0 + 2; ++j) {
        if (!topology.cell(i, j)) continue;
        for (int t = topology.first_triangle(i, j); t < topology.first_triangle(i, j) + 2; ++t)
          for (int k = 0; k < 3; ++k)
            nearby.push_back(topology.edge_index(topology.triangles[t][k], topology.triangles[t][(k + 1) % 3]));
      }
    std::sort(nearby.begin(), nearby.end());
    nearby.erase(std::unique(nearby.begin(), nearby.end()), nearby.end());
    for (int f : nearby) {
      const auto& b = topology.edges[f];
      if (f <= e || a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      if (!topology.near(a[0], b[0]) && !topology.near(a[0], b[1]) && !topology.near(a[1], b[0]) &&
          !topology.near(a[1], b[1]))
        continue;
      planes.clear();
      edge_planes(b, a, topology, planes);
      edge_planes(a, b, topology, planes);
      out.push_back({{SelfContactPair::Kind::EdgeEdge, {a[0], a[1], b[0], b[1]}}, best_plane(planes, rest, normals)});
    }
  }
}

Vec3 unit_or_zero(const Vec3& v) {
  const double length = v.norm();
  return length > 0.0 ? Vec3(v / length) : Vec3::Zero();
}

}  // namespace

void PlaneNormals::compute(const VecX& x, const std::vector<std::array<int, 3>>& triangles,
                           const std::vector<std::array<int, 2>>& edges) {
  triangle_edges_.resize(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3 p[3] = {x.segment<3>(3 * triangles[t][0]), x.segment<3>(3 * triangles[t][1]),
                       x.segment<3>(3 * triangles[t][2])};
    const Vec3 normal = (p[1] - p[0]).cross(p[2] - p[0]);
    for (int k = 0; k < 3; ++k) {
      // (b - a) x n lies in the plane, perpendicular to ab, facing away from the third vertex
      // for a counter-clockwise abc about n.
      const Vec3 edge = p[(k + 1) % 3] - p[k];
      triangle_edges_[3 * t + k] = unit_or_zero(edge.cross(normal));
    }
  }
  edges_.resize(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
    edges_[e] = unit_or_zero(x.segment<3>(3 * edges[e][1]) - x.segment<3>(3 * edges[e][0]));
}

double SeparatingPlane::separation(const VecX& x, const PlaneNormals& normals) const {
  Vec3 normal = kind == Kind::EdgeOfTriangle ? normals.triangle_edge(feature, slot) : normals.edge(feature);
  if (kind == Kind::AgainstEdge) normal = -normal;
  if (normal.isZero()) return -std::numeric_limits<double>::infinity();
  const Vec3 origin_position = x.segment<3>(3 * origin);
  double s = normal.dot(x.segment<3>(3 * front[0]) - origin_position);
  if (front[1] >= 0) s = std::min(s, normal.dot(x.segment<3>(3 * front[1]) - origin_position));
  return s;
}

std::vector<NeighbourPair> neighbour_pairs(const Grid& grid, const std::vector<std::array<int, 3>>& triangles,
                                           const std::vector<std::array<int, 2>>& edges) {
  const Topology topology{grid, triangles, edges};
  const VecX rest = grid.rest_positions();
  PlaneNormals normals;
  normals.compute(rest, triangles, edges);
  std::vector<NeighbourPair> out;
  point_triangle_pairs(topology, rest, normals, out);
  edge_edge_pairs(topology, rest, normals, out);
  std::sort(out.begin(), out.end(), [](const NeighbourPair& p, const NeighbourPair& q) { return p.pair < q.pair; });
  return out;
}

}  // namespace fnopt
