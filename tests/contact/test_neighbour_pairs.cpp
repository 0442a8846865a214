// The neighbour pairs of self-contact: exactly the vertex-disjoint pairs one grid step apart, each
// with a plane that separates it at rest by h/sqrt(2) or more and whose clearance never exceeds the
// pair's distance, whatever the state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <set>

#include <fnopt/contact/neighbour_pairs.hpp>
#include <fnopt/contact/primitive_distance.hpp>

namespace fnopt {
namespace {

struct Mesh {
  Grid grid;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> edges;
};

Mesh mesh(int rows, int cols) {
  Mesh m{Grid::make(rows, cols, 1.0), {}, {}};
  const auto t = m.grid.triangles();
  for (Eigen::Index k = 0; k < t.rows(); ++k) {
    m.triangles.push_back({t(k, 0), t(k, 1), t(k, 2)});
    for (int s = 0; s < 3; ++s) m.edges.push_back({std::min(t(k, s), t(k, (s + 1) % 3)), std::max(t(k, s), t(k, (s + 1) % 3))});
  }
  std::sort(m.edges.begin(), m.edges.end());
  m.edges.erase(std::unique(m.edges.begin(), m.edges.end()), m.edges.end());
  return m;
}

double distance(const VecX& x, const SelfContactPair& pair) {
  Vec12 local;
  for (int k = 0; k < 4; ++k) local.segment<3>(3 * k) = x.segment<3>(3 * pair.vertices[k]);
  return std::sqrt(pair.kind == SelfContactPair::Kind::PointTriangle
                       ? point_triangle_squared_distance(local, point_triangle_distance_type(local))
                       : edge_edge_squared_distance(local, edge_edge_distance_type(local)));
}

TEST(NeighbourPairs, AreExactlyTheVertexDisjointPairsOneGridStepApart) {
  const Mesh m = mesh(6, 7);
  auto near = [&](int a, int b) {
    return std::abs(a / m.grid.cols - b / m.grid.cols) <= 1 && std::abs(a % m.grid.cols - b % m.grid.cols) <= 1;
  };
  std::set<SelfContactPair> expected;
  for (int v = 0; v < m.grid.vertex_count(); ++v)
    for (const auto& t : m.triangles)
      if (v != t[0] && v != t[1] && v != t[2] && (near(v, t[0]) || near(v, t[1]) || near(v, t[2])))
        expected.insert({SelfContactPair::Kind::PointTriangle, {v, t[0], t[1], t[2]}});
  for (std::size_t e = 0; e < m.edges.size(); ++e)
    for (std::size_t f = e + 1; f < m.edges.size(); ++f) {
      const auto &a = m.edges[e], &b = m.edges[f];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      if (near(a[0], b[0]) || near(a[0], b[1]) || near(a[1], b[0]) || near(a[1], b[1]))
        expected.insert({SelfContactPair::Kind::EdgeEdge, {a[0], a[1], b[0], b[1]}});
    }
  std::set<SelfContactPair> found;
  for (const NeighbourPair& p : neighbour_pairs(m.grid, m.triangles, m.edges)) found.insert(p.pair);
  EXPECT_EQ(found, expected);
}

TEST(NeighbourPairs, EveryPlaneSeparatesAtRestAndNeverClaimsMoreThanTheDistance) {
  const Mesh m = mesh(7, 7);
  const std::vector<NeighbourPair> pairs = neighbour_pairs(m.grid, m.triangles, m.edges);
  const VecX rest = m.grid.rest_positions();
  PlaneNormals normals;
  normals.compute(rest, m.triangles, m.edges);
  for (const NeighbourPair& p : pairs) EXPECT_GE(p.plane.separation(rest, normals), m.grid.spacing / std::sqrt(2.0) - 1e-12);
  // Crumpled states, creased within a cell as much as across cells (a back vertex brought in front
  // of its plane): the clearance is a lower bound of the distance.
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 1.0 * m.grid.spacing);
  for (int trial = 0; trial < 200; ++trial) {
    VecX x = rest;
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
    normals.compute(x, m.triangles, m.edges);
    for (const NeighbourPair& p : pairs) ASSERT_LE(p.plane.separation(x, normals), distance(x, p.pair) + 1e-12);
  }
}

// A crease within a cell: the vertex of a pair's triangle that lies behind its plane at rest is
// carried in front of it, next to the pair's point; the clearance still bounds the distance.
TEST(NeighbourPairs, TheClearanceBoundsTheDistanceWhereTheBackPrimitiveCrossesItsPlane) {
  const Mesh m = mesh(7, 7);
  const VecX rest = m.grid.rest_positions();
  PlaneNormals normals;
  int tried = 0;
  for (const NeighbourPair& p : neighbour_pairs(m.grid, m.triangles, m.edges)) {
    if (p.pair.kind != SelfContactPair::Kind::PointTriangle) continue;
    const auto& tri = m.triangles[p.plane.feature];
    const int behind = tri[(p.plane.slot + 2) % 3];  // the triangle's vertex off the plane's edge
    VecX x = rest;
    x.segment<3>(3 * behind) = rest.segment<3>(3 * p.pair.vertices[0]) + Vec3(0.0, 0.0, 0.1 * m.grid.spacing);
    normals.compute(x, m.triangles, m.edges);
    ASSERT_LE(p.plane.separation(x, normals), distance(x, p.pair) + 1e-12);
    ++tried;
  }
  EXPECT_GT(tried, 100);
}

}  // namespace
}  // namespace fnopt
