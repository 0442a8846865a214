// surface_distance and disjoint_self_distance against every pair of primitives tried, after a
// build and after a refit; the surface's edges and vertices are those of its triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/metrics/surface_distance.hpp>

namespace fnopt {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A surface of `count` random triangles on `points` random points in a box of side `side`.
DistanceSurface random_surface(int points, int count, double side, std::mt19937& rng) {
  std::uniform_real_distribution<double> at(0.0, side);
  std::uniform_int_distribution<int> pick(0, points - 1);
  DistanceSurface s;
  for (int k = 0; k < points; ++k) s.points.emplace_back(at(rng), at(rng), at(rng));
  std::vector<std::array<int, 3>> triangles;
  while (static_cast<int>(triangles.size()) < count) {
    const std::array<int, 3> t = {pick(rng), pick(rng), pick(rng)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) triangles.push_back(t);
  }
  s.set_triangles(triangles);
  s.place();
  return s;
}

double brute_force(const DistanceSurface& a, const DistanceSurface& b, bool disjoint) {
  double best = kInfinity;
  auto shares = [](auto x, auto y) {
    for (int i : x)
      for (int j : y)
        if (i == j) return true;
    return false;
  };
  for (int v : a.vertices)
    for (const auto& t : b.triangles)
      if (!disjoint || !shares(std::array<int, 1>{v}, t))
        best = std::min(best, ccd_distance::point_triangle_squared(a.points[v], b.points[t[0]], b.points[t[1]],
                                                                   b.points[t[2]]));
  for (int v : b.vertices)
    for (const auto& t : a.triangles)
      if (!disjoint)
        best = std::min(best, ccd_distance::point_triangle_squared(b.points[v], a.points[t[0]], a.points[t[1]],
                                                                   a.points[t[2]]));
  for (const auto& e : a.edges)
    for (const auto& f : b.edges)
      if (!disjoint || !shares(e, f))
        best = std::min(best, ccd_distance::segment_segment_squared(a.points[e[0]], a.points[e[1]], b.points[f[0]],
                                                                    b.points[f[1]]));
  return std::sqrt(best);
}

TEST(SurfaceDistance, IsTheSmallestOverEveryPairTriedAfterBuildAndRefit) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    DistanceSurface a = random_surface(30, 40, 1.0, rng), b = random_surface(25, 30, 1.0, rng);
    for (Vec3& p : b.points) p += Vec3(0.3 + 0.1 * trial, 0.0, 0.0);  // from overlapping to apart
    b.place();
    EXPECT_NEAR(surface_distance(a, b), brute_force(a, b, false), 1e-12);
    EXPECT_NEAR(surface_distance(b, a), surface_distance(a, b), 1e-12);
    for (Vec3& p : a.points) p = 0.8 * p;  // every point moves: the trees are refitted
    a.place();
    EXPECT_NEAR(surface_distance(a, b), brute_force(a, b, false), 1e-12);
  }
}

TEST(SurfaceDistance, TheSelfDistanceSkipsOnlyPairsSharingAVertex) {
  std::mt19937 rng(6);
  for (int trial = 0; trial < 20; ++trial) {
    DistanceSurface s = random_surface(40, 30, 1.0, rng);
    EXPECT_NEAR(disjoint_self_distance(s), brute_force(s, s, true), 1e-12);
  }
  DistanceSurface one;  // one triangle: no vertex-disjoint pair
  one.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(5, 5, 5)};
  one.set_triangles({{0, 1, 2}});
  one.place();
  EXPECT_EQ(one.vertices, (std::vector<int>{0, 1, 2}));  // the point on no triangle is not on it
  EXPECT_EQ(disjoint_self_distance(one), kInfinity);
}

TEST(SurfaceDistance, AFlatGridHoldsItsDisjointPairsHOverRootTwoApart) {
  DistanceSurface cloth;
  const int n = 9;
  const double h = 0.125;
  cloth.set_grid(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) cloth.points.emplace_back(j * h, i * h, 0.0);
  cloth.place();
  EXPECT_EQ(static_cast<int>(cloth.vertices.size()), n * n);
  EXPECT_NEAR(disjoint_self_distance(cloth), h / std::sqrt(2.0), 1e-12);
}

}  // namespace
}  // namespace fnopt
