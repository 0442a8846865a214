// segment_meets_triangle on hand-made cases (through the interior, an edge, a vertex, touching,
// coplanar, parallel, missing by one ulp, degenerate triangles and segments), against a plain
// double test where that one is unambiguous, and under permutations; the counts against a
// brute-force loop over every (edge, triangle) pair on folded, crumpled and spiked grids and a
// tetrahedron, invariant under exact translations and scalings and the thread count.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <fnopt/cloth/grid.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>

#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using Edge = std::array<int, 2>;

// ---- segment_meets_triangle ----

const Vec3 A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);  // in the plane z = 0
constexpr double kUlp = 0x1p-52;                // one ulp of 1

bool meets(const Vec3& p, const Vec3& q) { return segment_meets_triangle(p, q, A, B, C); }

TEST(SegmentMeetsTriangle, CrossingTheInteriorAnEdgeOrAVertex) {
  EXPECT_TRUE(meets(Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, 1)));
  EXPECT_TRUE(meets(Vec3(0.1, 0.2, 1), Vec3(0.3, 0.1, -2)));  // oblique
  EXPECT_TRUE(meets(Vec3(0.5, 0, -1), Vec3(0.5, 0, 1)));      // through edge ab
  EXPECT_TRUE(meets(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1)));  // through edge bc
  EXPECT_TRUE(meets(Vec3(1, 0, -1), Vec3(1, 0, 1)));          // through vertex b
  EXPECT_TRUE(meets(Vec3(-1, -1, -1), Vec3(1, 1, 1)));        // through vertex a, obliquely
}

TEST(SegmentMeetsTriangle, TouchingAtAnEndpoint) {
  EXPECT_TRUE(meets(Vec3(0.25, 0.25, 0), Vec3(0.25, 0.25, 1)));
  EXPECT_TRUE(meets(Vec3(0.5, 0.5, 0), Vec3(3, 1, 1)));  // on edge bc
  EXPECT_TRUE(meets(Vec3(2, 2, 2), Vec3(0, 1, 0)));      // at vertex c
  EXPECT_FALSE(meets(Vec3(2, 2, 0), Vec3(2, 2, 1)));     // on the plane, beside the triangle
}

TEST(SegmentMeetsTriangle, MissingBesideAboveOrShort) {
  EXPECT_FALSE(meets(Vec3(2, 2, -1), Vec3(2, 2, 1)));
  EXPECT_FALSE(meets(Vec3(-0.1, 0.5, -1), Vec3(-0.1, 0.5, 1)));
  EXPECT_FALSE(meets(Vec3(0, 0, 1), Vec3(1, 0, 1)));                      // parallel above
  EXPECT_FALSE(meets(Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, -0x1p-60)));  // stops short
  EXPECT_FALSE(meets(Vec3(0.25, 0.25, 0x1p-1000), Vec3(0.3, 0.2, 1)));    // starts just above
}

// One ulp beside edge bc (x + y = 1) misses, on it meets: the plain double test cannot tell.
TEST(SegmentMeetsTriangle, DecidedExactlyAtOneUlp) {
  EXPECT_TRUE(meets(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 3)));
  EXPECT_FALSE(meets(Vec3(0.5, 0.5 + kUlp, -1), Vec3(0.5, 0.5 + kUlp, 3)));
  EXPECT_TRUE(meets(Vec3(0.5, 0.5 - kUlp, -1), Vec3(0.5, 0.5 - kUlp, 3)));
  // Obliquely, crossing the plane at (t/2, t + u, 0), t = fl(2/3), just beyond bc.
  const double t = 2.0 / 3;
  EXPECT_FALSE(meets(Vec3(0, t + kUlp, -1), Vec3(t, t + kUlp, 1)));
  EXPECT_TRUE(meets(Vec3(1 - t, t, -1), Vec3(1 - t, t, 1)));  // 1 - t is exact: on bc
}

TEST(SegmentMeetsTriangle, CoplanarOverlappingOrDisjoint) {
  EXPECT_TRUE(meets(Vec3(-1, 0.25, 0), Vec3(2, 0.25, 0)));       // across
  EXPECT_TRUE(meets(Vec3(0.1, 0.1, 0), Vec3(0.2, 0.3, 0)));      // inside
  EXPECT_TRUE(meets(Vec3(1, 0, 0), Vec3(2, 0, 0)));              // touching vertex b
  EXPECT_TRUE(meets(Vec3(-1, 0, 0), Vec3(0.5, 0, 0)));           // along edge ab
  EXPECT_TRUE(meets(Vec3(0.5, 0.5, 0), Vec3(2, 2, 0)));          // from edge bc outwards
  EXPECT_FALSE(meets(Vec3(1, 1, 0), Vec3(2, 0.5, 0)));           // beside
  EXPECT_FALSE(meets(Vec3(-2, 0, 0), Vec3(-1, 0, 0)));           // on ab's line, before a
  EXPECT_FALSE(meets(Vec3(0.5 + kUlp, 0.5, 0), Vec3(1, 1, 0)));  // one ulp beyond bc
  // A tilted coplanar case: the triangle and segment in the plane x + y + z = 1.
  EXPECT_TRUE(
      segment_meets_triangle(Vec3(0.25, 0.25, 0.5), Vec3(-1, 1, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)));
  EXPECT_FALSE(segment_meets_triangle(Vec3(1, 1, -1), Vec3(2, 0, -1), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)));
}

TEST(SegmentMeetsTriangle, DegenerateTrianglesAndSegments) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear: the segment from a to c
  EXPECT_TRUE(segment_meets_triangle(Vec3(1.5, -1, -1), Vec3(1.5, 1, 1), a, b, c));
  EXPECT_TRUE(segment_meets_triangle(Vec3(1.5, -1, 0), Vec3(1.5, 1, 0), c, a, b));
  EXPECT_TRUE(segment_meets_triangle(Vec3(2, 0, 0), Vec3(3, 0, 0), a, c, b));  // touching c
  EXPECT_FALSE(segment_meets_triangle(Vec3(3, -1, 0), Vec3(3, 1, 0), a, b, c));
  EXPECT_FALSE(segment_meets_triangle(Vec3(1.5, -1, 1), Vec3(1.5, 1, 1), a, b, c));  // above
  const Vec3 p(1, 1, 1);  // a triangle with all three vertices at p
  EXPECT_TRUE(segment_meets_triangle(Vec3(0, 0, 0), Vec3(2, 2, 2), p, p, p));
  EXPECT_FALSE(segment_meets_triangle(Vec3(0, 0, 0), Vec3(2, 2, 2 + 4 * kUlp), p, p, p));
  // A zero-length segment is its point.
  EXPECT_TRUE(meets(Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 0)));
  EXPECT_FALSE(meets(Vec3(0.7, 0.7, 0), Vec3(0.7, 0.7, 0)));
  EXPECT_FALSE(meets(Vec3(0.2, 0.2, 1), Vec3(0.2, 0.2, 1)));
  EXPECT_TRUE(segment_meets_triangle(b, b, a, b, c));
}

// Random segments and triangles, where the plain double test's margin is wide: same answer.
TEST(SegmentMeetsTriangle, AgreesWithPlainDoublesAwayFromTheBoundary) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int decided = 0, met = 0;
  for (int n = 0; n < 20000; ++n) {
    const Vec3 p(u(rng), u(rng), u(rng)), q(u(rng), u(rng), u(rng)), a(u(rng), u(rng), u(rng)),
        b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 normal = (b - a).cross(c - a);
    const double dp = normal.dot(p - a), dq = normal.dot(q - a), margin = 1e-6;
    if (std::fabs(dp) < margin || std::fabs(dq) < margin || normal.norm() < margin) continue;
    bool expected = false;
    if ((dp > 0) != (dq > 0)) {
      const Vec3 x = p + dp / (dp - dq) * (q - p);
      const double wa = normal.dot((b - x).cross(c - x)), wb = normal.dot((c - x).cross(a - x)),
                   wc = normal.dot((a - x).cross(b - x));
      if (std::min({std::fabs(wa), std::fabs(wb), std::fabs(wc)}) < margin) continue;
      expected = wa > 0 && wb > 0 && wc > 0;
    }
    ASSERT_EQ(segment_meets_triangle(p, q, a, b, c), expected) << "case " << n;
    ++decided;
    met += expected;
  }
  EXPECT_GT(decided, 15000);
  EXPECT_GT(met, 500);
}

// Small integer coordinates (many coplanar, collinear and coincident cases): the answer does not
// depend on the order of the triangle's vertices, the segment's direction or a translation.
TEST(SegmentMeetsTriangle, InvariantUnderPermutationsAndTranslation) {
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<int> u(-2, 2);
  int met = 0;
  for (int n = 0; n < 20000; ++n) {
    std::array<Vec3, 5> v;
    for (Vec3& x : v) x = Vec3(u(rng), u(rng), n % 2 ? u(rng) : 0);  // every second case in a plane
    const bool expected = segment_meets_triangle(v[0], v[1], v[2], v[3], v[4]);
    met += expected;
    std::array<int, 3> order = {2, 3, 4};
    do {
      ASSERT_EQ(segment_meets_triangle(v[1], v[0], v[order[0]], v[order[1]], v[order[2]]), expected) << n;
    } while (std::next_permutation(order.begin(), order.end()));
    const Vec3 t(1024.5, -3.25, 7);
    ASSERT_EQ(segment_meets_triangle(v[0] + t, v[1] + t, v[2] + t, v[3] + t, v[4] + t), expected) << n;
  }
  EXPECT_GT(met, 2000);
  EXPECT_LT(met, 18000);
}

// ---- The counts against brute force ----

// The grid's edges written out: horizontal, vertical, and the diagonal (i,j)-(i+1,j+1).
std::vector<Edge> grid_edges(int rows, int cols) {
  std::vector<Edge> edges;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const int k = i * cols + j;
      if (j + 1 < cols) edges.push_back({k, k + 1});
      if (i + 1 < rows) edges.push_back({k, k + cols});
      if (i + 1 < rows && j + 1 < cols) edges.push_back({k, k + cols + 1});
    }
  return edges;
}

std::vector<Eigen::Vector3i> grid_triangles(int rows, int cols) {
  const auto t = Grid{rows, cols, 1.0}.triangles();
  std::vector<Eigen::Vector3i> triangles;
  for (Eigen::Index f = 0; f < t.rows(); ++f) triangles.emplace_back(t(f, 0), t(f, 1), t(f, 2));
  return triangles;
}

std::vector<Vec3> as_points(const Eigen::VectorXf& x) {
  std::vector<Vec3> points;
  for (Eigen::Index k = 0; 3 * k < x.size(); ++k) points.push_back(x.segment<3>(3 * k).cast<double>());
  return points;
}

// Every edge against every triangle, with segment_meets_triangle; `skip_shared` leaves out pairs
// with a common vertex (one mesh).
long brute_force(const std::vector<Vec3>& edge_points, const std::vector<Edge>& edges,
                 const std::vector<Vec3>& triangle_points, const std::vector<Eigen::Vector3i>& triangles,
                 bool skip_shared) {
  long count = 0;
  for (const Edge& e : edges)
    for (const Eigen::Vector3i& t : triangles) {
      if (skip_shared && (t.array() == e[0]).any()) continue;
      if (skip_shared && (t.array() == e[1]).any()) continue;
      const std::vector<Vec3>& x = edge_points;
      const std::vector<Vec3>& y = triangle_points;
      count += segment_meets_triangle(x[e[0]], x[e[1]], y[t[0]], y[t[1]], y[t[2]]);
    }
  return count;
}

long brute_force_self(const Eigen::VectorXf& x, int rows, int cols) {
  const std::vector<Vec3> points = as_points(x);
  return brute_force(points, grid_edges(rows, cols), points, grid_triangles(rows, cols), true);
}

// Vertex (i, j) at (j, i, 0) (times `spacing`) plus, in each coordinate, a uniform number in
// [-noise, noise] rounded to a multiple of 2^-10 (so that translations by dyadic offsets are exact).
Eigen::VectorXf crumpled_grid(int rows, int cols, double noise, unsigned seed, double spacing = 1.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  Eigen::VectorXf x(3 * rows * cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const Vec3 p = Vec3(j, i, 0) * spacing + Vec3(u(rng), u(rng), u(rng));
      x.segment<3>(3 * (i * cols + j)) = ((p * 1024).array().round() / 1024).matrix().cast<float>();
    }
  return x;
}

// Rows 0..4 flat at z = 0; rows 5.. turn back under them, rise through them between rows 5 and 6
// and continue above, shifted by half a cell in x.
Eigen::VectorXf folded_grid(int rows, int cols) {
  Eigen::VectorXf x(3 * rows * cols);
  const int m = 4;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const Vec3 p = i <= m ? Vec3(j, i, 0) : Vec3(j + 0.5, m - (i - m) + 0.25, -1.5 + (i - m));
      x.segment<3>(3 * (i * cols + j)) = p.cast<float>();
    }
  return x;
}

Eigen::VectorXf translated(Eigen::VectorXf x, const Eigen::Vector3f& offset) {
  for (Eigen::Index k = 0; 3 * k < x.size(); ++k) x.segment<3>(3 * k) += offset;
  return x;
}

TEST(CountSelfIntersections, FlatGridsHaveNone) {
  EXPECT_EQ(count_self_intersections(crumpled_grid(12, 9, 0.0, 1), 12, 9), 0);
  Eigen::VectorXf rest = Grid::make(20, 20, 1.0).rest_positions().cast<float>();  // the x-z plane
  EXPECT_EQ(count_self_intersections(rest, 20, 20), 0);
  // Exactly in the tilted plane x + y + z = 0: coplanar everywhere, the filter cannot decide.
  Eigen::VectorXf tilted(3 * 10 * 10);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) tilted.segment<3>(3 * (10 * i + j)) = Eigen::Vector3f(j, i, -(i + j));
  EXPECT_EQ(count_self_intersections(tilted, 10, 10), 0);
}

TEST(CountSelfIntersections, FoldedGridMatchesBruteForce) {
  const Eigen::VectorXf x = folded_grid(10, 6);
  const long count = count_self_intersections(x, 10, 6);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute_force_self(x, 10, 6));
  EXPECT_EQ(count_self_intersections(translated(x, Eigen::Vector3f(16, -8.5, 3.25)), 10, 6), count);
}

TEST(CountSelfIntersections, CrumpledGridsMatchBruteForce) {
  long total = 0;
  for (unsigned seed = 0; seed < 40; ++seed) {
    const Eigen::VectorXf x = crumpled_grid(6, 6, 0.9, seed);
    const long count = count_self_intersections(x, 6, 6);
    ASSERT_EQ(count, brute_force_self(x, 6, 6)) << "seed " << seed;
    ASSERT_EQ(count_self_intersections(translated(x, Eigen::Vector3f(8, -4, 2.5)), 6, 6), count) << "seed " << seed;
    ASSERT_EQ(count_self_intersections(x * 0x1p-40f, 6, 6), count) << "seed " << seed;
    total += count;
  }
  EXPECT_GT(total, 40);
  for (const double noise : {0.3, 3.0}) {  // barely crumpled, and boxes over many cells
    const Eigen::VectorXf x = crumpled_grid(11, 9, noise, 7);
    EXPECT_EQ(count_self_intersections(x, 11, 9), brute_force_self(x, 11, 9)) << noise;
  }
}

// A vertex pulled far out across the cloth (a diverging frame): its edges' and triangles' boxes
// span many cells and are tested against everything.
TEST(CountSelfIntersections, SpikedGridMatchesBruteForce) {
  Eigen::VectorXf x = crumpled_grid(9, 9, 0.2, 3);
  x.segment<3>(3 * 10) = Eigen::Vector3f(400, 370, 0.125);
  x.segment<3>(3 * 70) = Eigen::Vector3f(3.5, -2, 50);
  const long count = count_self_intersections(x, 9, 9);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute_force_self(x, 9, 9));
}

TEST(CountSelfIntersections, SameOnAnyThreadCount) {
#ifdef _OPENMP
  const Eigen::VectorXf x = crumpled_grid(40, 40, 0.8, 5);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const long serial = count_self_intersections(x, 40, 40);
  omp_set_num_threads(4);
  const long parallel = count_self_intersections(x, 40, 40);
  omp_set_num_threads(threads);
  EXPECT_GT(serial, 0);
  EXPECT_EQ(parallel, serial);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}

TEST(CountSelfIntersections, RejectsNonFiniteAndMisshapenFrames) {
  Eigen::VectorXf x = crumpled_grid(4, 5, 0.1, 1);
  EXPECT_TRUE(testing::throws_error([&] { count_self_intersections(x, 5, 5); }, "positions: holds 60 values"));
  EXPECT_TRUE(testing::throws_error([&] { count_self_intersections(x, 0, 5); }, "rows, cols"));
  x[3 * 7 + 1] = NAN;
  EXPECT_TRUE(testing::throws_error([&] { count_self_intersections(x, 4, 5); },
                                    "positions: vertex 7 (row 1, column 2) is not finite"));
  x[3 * 7 + 1] = INFINITY;
  EXPECT_TRUE(testing::throws_error([&] { count_self_intersections(x, 4, 5); }, "vertex 7"));
}

// ---- Mesh intersections ----

// A tetrahedron with corners (0,0,0), (2,0,0), (0,2,0), (0,0,2), faces outward.
const std::vector<Vec3> kTetVertices = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 2)};
const std::vector<Eigen::Vector3i> kTetTriangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// An 8 x 8 cloth of spacing 0.5 over [-1, 2.5]^2 at height z (with a small tilt in y when asked).
Eigen::VectorXf cloth_at(float z, float tilt = 0) {
  Eigen::VectorXf x(3 * 64);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      x.segment<3>(3 * (8 * i + j)) = Eigen::Vector3f(-1 + 0.5f * j, -1 + 0.5f * i, z + tilt * i);
  return x;
}

long brute_force_mesh(const Eigen::VectorXf& x, const std::vector<Vec3>& vertices,
                      const std::vector<Eigen::Vector3i>& triangles) {
  std::set<Edge> unique;
  for (const Eigen::Vector3i& t : triangles)
    for (int k = 0; k < 3; ++k) unique.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  const std::vector<Vec3> cloth = as_points(x);
  return brute_force(cloth, grid_edges(8, 8), vertices, triangles, false) +
         brute_force(vertices, {unique.begin(), unique.end()}, cloth, grid_triangles(8, 8), false);
}

TEST(CountMeshIntersections, ClothAboveATetrahedronHasNone) {
  EXPECT_EQ(count_mesh_intersections(cloth_at(2.5f), 8, 8, kTetVertices, kTetTriangles), 0);
  EXPECT_EQ(count_mesh_intersections(cloth_at(2.0f + 0x1p-20f), 8, 8, kTetVertices, kTetTriangles), 0);
}

TEST(CountMeshIntersections, ClothThroughATetrahedronMatchesBruteForce) {
  // Through the middle, tilted, touching the apex (touching counts), on the base face.
  for (const auto& [z, tilt] :
       std::vector<std::pair<float, float>>{{1.0f, 0.0f}, {0.3f, 0.1f}, {2.0f, 0.0f}, {0.0f, 0.0f}}) {
    const Eigen::VectorXf x = cloth_at(z, tilt);
    const long count = count_mesh_intersections(x, 8, 8, kTetVertices, kTetTriangles);
    EXPECT_GT(count, 0) << z;
    EXPECT_EQ(count, brute_force_mesh(x, kTetVertices, kTetTriangles)) << z;
  }
  // A crumpled cloth through a larger tetrahedron, and translated with it.
  std::vector<Vec3> big = kTetVertices;
  for (Vec3& v : big) v = 3 * v + Vec3(-0.75, -0.5, -1.25);
  const Eigen::VectorXf x = crumpled_grid(8, 8, 0.6, 9, 0.5);
  const long count = count_mesh_intersections(x, 8, 8, big, kTetTriangles);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute_force_mesh(x, big, kTetTriangles));
  for (Vec3& v : big) v += Vec3(4, -2, 8);
  EXPECT_EQ(count_mesh_intersections(translated(x, Eigen::Vector3f(4, -2, 8)), 8, 8, big, kTetTriangles), count);
}

TEST(CountMeshIntersections, RejectsBadMeshes) {
  const Eigen::VectorXf x = cloth_at(1.0f);
  EXPECT_TRUE(testing::throws_error(
      [&] {
        count_mesh_intersections(x, 8, 8, kTetVertices, {{0, 1, 4}});
      },
      "mesh triangles: triangle 0 refers to vertex 4, the mesh has 4"));
  std::vector<Vec3> vertices = kTetVertices;
  vertices[2].y() = NAN;
  EXPECT_TRUE(testing::throws_error([&] { count_mesh_intersections(x, 8, 8, vertices, kTetTriangles); },
                                    "mesh vertices: vertex 2 is not finite"));
  // A triangle with a repeated index: its one distinct edge counts, as a segment.
  EXPECT_EQ(count_mesh_intersections(x, 8, 8, {Vec3(0.1, 0.2, 0), Vec3(0.1, 0.2, 2)}, {{0, 1, 1}}), 1);
}

}  // namespace
}  // namespace fnopt
