// orient3d_sign and orient2d_sign against exact integer determinants (__int128) on integer
// coordinates, on near-degenerate inputs where the plain double formula gets the sign wrong
// (Shewchuk's ulp-perturbed points, slivers), on exactly coplanar points scaled by powers of two
// and translated, on inputs whose exponents force each exact stage, and under permutations.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <fnopt/metrics/exact_predicates.hpp>

namespace fnopt {
namespace {

__extension__ typedef __int128 Int128;
using Point2 = Eigen::Vector2d;
using Ints3 = std::array<long long, 12>;  // a, b, c, d
using Ints2 = std::array<long long, 6>;   // a, b, c

int sign_of(Int128 x) { return (x > 0) - (x < 0); }

// det[b - a, c - a, d - a] exactly (coordinates below 2^38 in magnitude: no overflow).
int reference3(const Ints3& x) {
  Int128 u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) u[k] = x[3 + k] - x[k], v[k] = x[6 + k] - x[k], w[k] = x[9 + k] - x[k];
  return sign_of(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                 u[2] * (v[0] * w[1] - v[1] * w[0]));
}

int reference2(const Ints2& x) {
  const Int128 ux = x[2] - x[0], uy = x[3] - x[1], vx = x[4] - x[0], vy = x[5] - x[1];
  return sign_of(ux * vy - uy * vx);
}

// The points as doubles, coordinate k scaled by 2^shift[k] and first translated by offset[k].
std::array<Vec3, 4> points3(const Ints3& x, std::array<int, 3> shift = {0, 0, 0},
                            std::array<long long, 3> offset = {}) {
  std::array<Vec3, 4> p;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) p[i][k] = std::ldexp(static_cast<double>(x[3 * i + k] + offset[k]), shift[k]);
  return p;
}

std::array<Point2, 3> points2(const Ints2& x, std::array<int, 2> shift = {0, 0}) {
  std::array<Point2, 3> p;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) p[i][k] = std::ldexp(static_cast<double>(x[2 * i + k]), shift[k]);
  return p;
}

int orient3d(const std::array<Vec3, 4>& p) { return orient3d_sign(p[0], p[1], p[2], p[3]); }

// The plain double formula, for showing that a test's inputs defeat it.
int naive3(const std::array<Vec3, 4>& p) {
  const double det = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]));
  return (det > 0) - (det < 0);
}

Ints3 random_ints3(std::mt19937_64& rng, long long range) {
  std::uniform_int_distribution<long long> u(-range, range);
  Ints3 x;
  for (long long& v : x) v = u(rng);
  return x;
}

// Slivers: b - a long, c - a = (b - a) + a short vector, d = a + s (b - a) + t (c - a) + e with
// small integers s, t and e in {-1, 0, 1}^3 (e = 0: exactly coplanar). The exact determinant is
// e . ((b - a) x (c - a)), tiny beside the products the plain formula rounds.
std::vector<Ints3> slivers(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<long long> base(-(1LL << 36), 1LL << 36), along(-(1LL << 35), 1LL << 35), small(-8, 8),
      weight(-2, 2), unit(-1, 1);
  std::vector<Ints3> cases;
  for (int n = 0; n < count; ++n) {
    Ints3 x;
    const long long s = weight(rng), t = weight(rng);
    for (int k = 0; k < 3; ++k) {
      const long long a = base(rng), u = along(rng), v = u + small(rng);
      x[k] = a, x[3 + k] = a + u, x[6 + k] = a + v, x[9 + k] = a + s * u + t * v + unit(rng);
    }
    cases.push_back(x);
  }
  return cases;
}

TEST(Orient3d, MatchesExactIntegerDeterminantOnRandomIntegers) {
  std::mt19937_64 rng(1);
  for (const long long range : {3LL, 1000LL, 1LL << 37})
    for (int n = 0; n < 20000; ++n) {
      const Ints3 x = random_ints3(rng, range);
      ASSERT_EQ(orient3d(points3(x)), reference3(x)) << "range " << range << ", case " << n;
    }
}

TEST(Orient3d, DecidesSliversThatDefeatPlainDoubles) {
  int naive_wrong = 0, coplanar = 0;
  for (const Ints3& x : slivers(20000, 2)) {
    const std::array<Vec3, 4> p = points3(x);
    ASSERT_EQ(orient3d(p), reference3(x));
    naive_wrong += naive3(p) != reference3(x);
    coplanar += reference3(x) == 0;
  }
  EXPECT_GT(naive_wrong, 1000);  // the inputs are hard: the plain formula fails on many
  EXPECT_GT(coplanar, 100);
}

// Shewchuk's figure: points p = (0.5 + i u, 0.5 + j u, 0.5 + (i + j) u), u = 2^-53 (one ulp of
// 0.5), against the plane through a = (12, 12, 12), b = (24, 24, 24), c = (12, 12, 0), which is
// x = y: det[b - a, c - a, p - a] = 144 (p_y - p_x).
TEST(Orient3d, DecidesUlpPerturbedPointsNearAPlane) {
  const Vec3 a(12, 12, 12), b(24, 24, 24), c(12, 12, 0);
  int naive_wrong = 0;
  for (int i = 0; i < 128; ++i)
    for (int j = 0; j < 128; ++j) {
      const double u = 0x1p-53;
      const std::array<Vec3, 4> p = {a, b, c, Vec3(0.5 + i * u, 0.5 + j * u, 0.5 + (i + j) * u)};
      const int expected = (j > i) - (j < i);
      ASSERT_EQ(orient3d(p), expected) << i << ", " << j;
      naive_wrong += naive3(p) != expected;
    }
  EXPECT_GT(naive_wrong, 100);
}

TEST(Orient2d, DecidesUlpPerturbedPointsNearALine) {  // Shewchuk's figure: the line y = x
  const Point2 a(12, 12), b(24, 24);
  int naive_wrong = 0;
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j) {
      const Point2 p(0.5 + i * 0x1p-53, 0.5 + j * 0x1p-53);
      const int expected = (j > i) - (j < i);  // det[b - a, p - a] = 12 (p_y - p_x)
      ASSERT_EQ(orient2d_sign(a, b, p), expected) << i << ", " << j;
      const double naive = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x();
      naive_wrong += ((naive > 0) - (naive < 0)) != expected;
    }
  EXPECT_GT(naive_wrong, 1000);
}

// Every coordinate scaled by the same power of two, then by different ones per axis (the
// determinant scales by a positive factor), and translated by integers (exact): the sign stays.
// The shifts take the inputs through each stage: the filter and expansions as given, after a
// scaling into range (exponents within 2^500 of each other), and as integers (further apart).
TEST(Orient3d, SignSurvivesPowerOfTwoScalingAndTranslation) {
  const std::vector<std::array<int, 3>> shifts = {
      {0, 0, 0},        {-1000, -1000, -1000}, {-600, -600, -600}, {300, 300, 300}, {900, 900, 900},
      {-300, 100, 150}, {0, 0, 400},           {-900, 0, 0},       {-1000, 0, 900}, {-1030, 950, 0}};
  const std::vector<std::array<long long, 3>> offsets = {{0, 0, 0}, {1LL << 50, -(1LL << 49), 12345}};
  std::mt19937_64 rng(3);
  std::vector<Ints3> cases = slivers(500, 4);
  for (int n = 0; n < 500; ++n) cases.push_back(random_ints3(rng, n % 2 ? 5 : 1LL << 37));
  for (const Ints3& x : cases)
    for (const auto& shift : shifts)
      for (const auto& offset : offsets)
        ASSERT_EQ(orient3d(points3(x, shift, offset)), reference3(x)) << shift[0] << " " << shift[1] << " " << shift[2];
}

// Determinants whose products underflow or overflow in doubles: 2^-2100, 2^2100, and one over
// exponents 1500 apart.
TEST(Orient3d, ExactBeyondTheRangeOfDoubleProducts) {
  const Vec3 o = Vec3::Zero();
  for (const double s : {0x1p-700, 0x1p+700}) {
    const Vec3 x(s, 0, 0), y(0, s, 0), z(0, 0, s);
    EXPECT_EQ(orient3d_sign(o, x, y, z), 1);
    EXPECT_EQ(orient3d_sign(o, y, x, z), -1);
    EXPECT_EQ(orient3d_sign(x, y, z, (x + y) * 0.5), 0);
    EXPECT_EQ(orient3d_sign(x, y, z, Vec3(s, s, -s)), 0);  // x + y - z lies on the plane of x, y, z
  }
  const Vec3 x(0x1p-1000, 0, 0), y(0, 0x1p500, 0), z(0, 0, 1);
  EXPECT_EQ(orient3d_sign(o, x, y, z), 1);
  EXPECT_EQ(orient3d_sign(o, x, z, y), -1);
  EXPECT_EQ(orient3d_sign(x, y, z, Vec3(0x1p-1000, 0x1p500, -1)), 0);  // x + y - z
  EXPECT_EQ(orient3d_sign(Vec3(0x1p-1074, 0, 0), Vec3(0, 0x1p-1074, 0), Vec3(0, 0, 0x1p-1074), Vec3(1e300, 0, 0)), 1);
}

// Odd permutations of the four points negate the sign, even ones keep it.
TEST(Orient3d, AntisymmetricUnderSwappingTwoPoints) {
  std::mt19937_64 rng(5);
  std::vector<Ints3> cases = slivers(2000, 6);
  for (int n = 0; n < 2000; ++n) cases.push_back(random_ints3(rng, 4));
  for (const Ints3& x : cases) {
    const auto [a, b, c, d] = points3(x);
    const int s = orient3d_sign(a, b, c, d);
    ASSERT_EQ(orient3d_sign(b, a, c, d), -s);
    ASSERT_EQ(orient3d_sign(a, c, b, d), -s);
    ASSERT_EQ(orient3d_sign(a, b, d, c), -s);
    ASSERT_EQ(orient3d_sign(d, b, c, a), -s);
    ASSERT_EQ(orient3d_sign(b, c, a, d), s);
    ASSERT_EQ(orient3d_sign(b, a, d, c), s);
    ASSERT_EQ(orient3d_sign(a, a, c, d), 0);
  }
}

TEST(Orient3d, SignConventionIsTheNormalsSide) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);  // counter-clockwise seen from +z: normal +z
  EXPECT_EQ(orient3d_sign(a, b, c, Vec3(0.2, 0.3, 1)), 1);
  EXPECT_EQ(orient3d_sign(a, b, c, Vec3(0.2, 0.3, -1)), -1);
  EXPECT_EQ(orient3d_sign(a, b, c, Vec3(5, -7, 0)), 0);
  EXPECT_EQ(orient2d_sign(Point2(0, 0), Point2(1, 0), Point2(0, 1)), 1);
  EXPECT_EQ(orient2d_sign(Point2(0, 0), Point2(0, 1), Point2(1, 0)), -1);
}

TEST(Orient2d, MatchesExactIntegerDeterminantAcrossScalings) {
  std::mt19937_64 rng(7);
  const std::vector<std::array<int, 2>> shifts = {{0, 0}, {-1000, -1000}, {600, 600}, {-300, 150}, {-1000, 900}};
  for (const long long range : {3LL, 1LL << 40})
    for (int n = 0; n < 20000; ++n) {
      std::uniform_int_distribution<long long> u(-range, range);
      Ints2 x;
      for (long long& v : x) v = u(rng);
      if (n % 3 == 0)  // c on the line ab, or one step off it
        for (int k = 0; k < 2; ++k) x[4 + k] = x[k] + 2 * (x[2 + k] - x[k]) + (n % 2) * (k == 0);
      for (const auto& shift : shifts) {
        const auto [a, b, c] = points2(x, shift);
        ASSERT_EQ(orient2d_sign(a, b, c), reference2(x)) << "case " << n;
        ASSERT_EQ(orient2d_sign(b, a, c), -reference2(x));
        ASSERT_EQ(orient2d_sign(b, c, a), reference2(x));
      }
    }
}

}  // namespace
}  // namespace fnopt
