// Additive CCD (contact/additive_ccd.hpp, docs/design.md §14): its distances against Ericson's
// closest-point routines (Real-Time Collision Detection, 2005, §5.1.5 and §5.1.9), a different
// construction for the point and triangle, and the segments' against the naive search over the
// candidates from crossing to parallel too; head-on approaches against their analytic first contact; the cases with no
// contact; and random motions against the path sampled densely with those reference distances:
// safe before the returned s, and 1 where the path never gets close enough to stop the search.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/box.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

using ccd_distance::point_segment_squared;
using ccd_distance::point_triangle_squared;
using ccd_distance::segment_segment_squared;

// Ericson's ClosestPtPointTriangle: the Voronoi region of p among the corners, edges and face.
// Needs a non-degenerate triangle.
double reference_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double v = vb / (va + vb + vc), w = vc / (va + vb + vc);
  return (p - (a + v * ab + w * ac)).norm();
}

// Ericson's ClosestPtSegmentSegment: the lines' parameters, clamped, one re-solved after the other.
double reference_segment_segment(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.dot(d1), e = d2.dot(d2), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a == 0.0 && e == 0.0) return r.norm();
  if (a == 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e == 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom != 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p1 + s * d1 - (p2 + t * d2)).norm();
}

// The naive search on the square (u, v) in [0, 1]²: the smallest of the four end-to-segment
// distances and, where the lines' closest pair lies inside the square, theirs.
double exhaustive_segment_segment(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  double best = std::min({point_segment_squared(a0, b0, b1), point_segment_squared(a1, b0, b1),
                          point_segment_squared(b0, a0, a1), point_segment_squared(b1, a0, a1)});
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double aa = da.squaredNorm(), bb = db.squaredNorm(), ab = da.dot(db);
  const double det = aa * bb - ab * ab;
  if (det > 0.0) {
    const double u = (ab * db.dot(r) - da.dot(r) * bb) / det, v = (aa * db.dot(r) - ab * da.dot(r)) / det;
    if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) best = std::min(best, (r + u * da - v * db).squaredNorm());
  }
  return std::sqrt(best);
}

// A motion of four vertices: the point and the triangle's corners, or edge a's ends then edge b's.
struct Motion {
  std::array<Vec3, 4> from, to;
  Vec3 at(int i, double s) const { return from[i] + s * (to[i] - from[i]); }
};

double pt_distance(const Motion& m, double s) {
  return reference_point_triangle(m.at(0, s), m.at(1, s), m.at(2, s), m.at(3, s));
}
double ee_distance(const Motion& m, double s) {
  return reference_segment_segment(m.at(0, s), m.at(1, s), m.at(2, s), m.at(3, s));
}
double pt_fraction(const Motion& m, double separation, const AdditiveCcdParams& params = {}) {
  return point_triangle_safe_fraction(m.from[0], m.from[1], m.from[2], m.from[3], m.to[0], m.to[1], m.to[2], m.to[3],
                                      separation, params);
}
double ee_fraction(const Motion& m, double separation, const AdditiveCcdParams& params = {}) {
  return edge_edge_safe_fraction(m.from[0], m.from[1], m.from[2], m.from[3], m.to[0], m.to[1], m.to[2], m.to[3],
                                 separation, params);
}

// l_p of the motion, vertices 0..split-1 one primitive and split..3 the other: the bound on how
// fast the distance can change per unit of s (the mean displacement removed).
double lipschitz_bound(const Motion& m, int split) {
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < 4; ++i) mean += (m.to[i] - m.from[i]) / 4.0;
  double first = 0.0, second = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double move = (m.to[i] - m.from[i] - mean).norm();
    if (i < split)
      first = std::max(first, move);
    else
      second = std::max(second, move);
  }
  return first + second;
}

Vec3 random_vec(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

TEST(AdditiveCcd, ParamsValidateNamesTheField) {
  EXPECT_NO_THROW(AdditiveCcdParams{}.validate());
  for (double eta : {0.0, 1.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    AdditiveCcdParams params;
    params.conservative_rescaling = eta;
    try {
      params.validate();
      ADD_FAILURE() << "eta " << eta << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), "ccd.conservative_rescaling");
    }
  }
  AdditiveCcdParams params;
  params.max_iterations = 0;
  try {
    params.validate();
    ADD_FAILURE() << "max_iterations 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "ccd.max_iterations");
  }
}

TEST(AdditiveCcd, DistancesAgreeWithEricson) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 p = random_vec(rng, 1.0), a = random_vec(rng, 1.0), b = random_vec(rng, 1.0), c = random_vec(rng, 1.0);
    EXPECT_NEAR(std::sqrt(point_triangle_squared(p, a, b, c)), reference_point_triangle(p, a, b, c), 1e-12);
    EXPECT_NEAR(std::sqrt(segment_segment_squared(p, a, b, c)), reference_segment_segment(p, a, b, c), 1e-12);
  }
}

// From crossing to exactly parallel: edge b is edge a turned by an angle from 1 rad down to 1e-9
// and 0, shifted along and across it, so the closest pair lies inside or at either end.
TEST(AdditiveCcd, SegmentDistanceIsTheNaiveMinimumAtEveryAngle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> shift(-1.5, 1.5);
  for (int trial = 0; trial < 4000; ++trial) {
    const Vec3 a0 = random_vec(rng, 1.0), a1 = random_vec(rng, 1.0);
    const double angle = trial % 11 == 10 ? 0.0 : std::pow(10.0, -(trial % 11) * 0.9);
    const Eigen::AngleAxisd turn(angle, random_vec(rng, 1.0).normalized());
    const Vec3 along = shift(rng) * (a1 - a0), across = 0.3 * random_vec(rng, 1.0);
    const Vec3 b0 = a0 + along + across, b1 = b0 + turn * (a1 - a0) * (0.5 + std::abs(shift(rng)));
    const double naive = exhaustive_segment_segment(a0, a1, b0, b1);
    EXPECT_NEAR(std::sqrt(segment_segment_squared(a0, a1, b0, b1)), naive, 1e-12 * (1.0 + naive))
        << "angle " << angle << " trial " << trial;
    EXPECT_NEAR(std::sqrt(segment_segment_squared(b0, b1, a0, a1)), naive, 1e-12 * (1.0 + naive));
  }
}

TEST(AdditiveCcd, DistancesOfSpecialConfigurations) {
  const Vec3 t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  EXPECT_DOUBLE_EQ(point_triangle_squared(Vec3(0.2, 0.3, -0.5), t0, t1, t2), 0.25);  // above the face
  EXPECT_DOUBLE_EQ(point_triangle_squared(Vec3(2, 0, 0), t0, t1, t2), 1.0);          // beyond a corner
  EXPECT_DOUBLE_EQ(point_triangle_squared(Vec3(1, 1, 0), t0, t1, t2), 0.5);          // beside the hypotenuse
  // A degenerate triangle (collinear corners) is its longest edge; a point triangle is the point.
  EXPECT_DOUBLE_EQ(point_triangle_squared(Vec3(1, 1, 0), t0, t1, Vec3(2, 0, 0)), 1.0);
  EXPECT_DOUBLE_EQ(point_triangle_squared(Vec3(1, 2, 2), t1, t1, t1), 8.0);
  EXPECT_DOUBLE_EQ(point_segment_squared(Vec3(0.5, 3, 0), t0, t1), 9.0);
  // Parallel overlapping segments, collinear ones with a gap, crossing ones, a point segment.
  EXPECT_DOUBLE_EQ(segment_segment_squared(t0, t1, Vec3(0.5, 0, 0.3), Vec3(1.5, 0, 0.3)), 0.09);
  EXPECT_DOUBLE_EQ(segment_segment_squared(t0, t1, Vec3(3, 0, 0), Vec3(2, 0, 0)), 1.0);
  EXPECT_NEAR(segment_segment_squared(Vec3(-1, 0, 0), t1, Vec3(0, -1, 0.2), Vec3(0, 1, 0.2)), 0.04, 1e-15);
  EXPECT_DOUBLE_EQ(segment_segment_squared(t2, t2, t0, t1), 1.0);
}

// Head-on: the point falls through the triangle's interior at constant velocity while the
// triangle rises, so the distance is 1 - 2.5 s and the first contact at separation d is
// t* = (1 - d)/2.5, where the distance equals d. The relative motion is a translation, so l_p is
// exactly the closing speed and each step closes η of the gap: the first lands at η t* with
// (1 - η) of the gap left, the next would leave (1 - η)², below the stop, so s = η t*. The test
// holds s to [0.8 t*, t*] and to η t* within rounding.
TEST(AdditiveCcd, PointThroughTriangleStopsShortOfTheAnalyticContact) {
  const Motion m{{Vec3(0.2, 0.3, 1.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                 {Vec3(0.2, 0.3, -1.0), Vec3(0, 0, 0.5), Vec3(1, 0, 0.5), Vec3(0, 1, 0.5)}};
  for (double separation : {0.0, 0.01, 0.1}) {
    const double contact = (1.0 - separation) / 2.5;
    EXPECT_NEAR(pt_distance(m, contact), separation, 1e-14);
    const double s = pt_fraction(m, separation);
    EXPECT_LE(s, contact);
    EXPECT_GE(s, 0.8 * contact);
    EXPECT_NEAR(s, 0.9 * contact, 1e-12);
    EXPECT_GT(pt_distance(m, s), separation);
  }
  AdditiveCcdParams half;
  half.conservative_rescaling = 0.5;
  EXPECT_NEAR(pt_fraction(m, 0.1, half), 0.5 * 0.36, 1e-12);
}

// Edge a (along x, at height 1) falls to height -1 across edge b (along y, at rest): the distance
// is 1 - 2s, contact at separation d at t* = (1 - d)/2; s = η t* as for the point above.
TEST(AdditiveCcd, CrossingEdgesStopShortOfTheAnalyticContact) {
  const Motion m{{Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(0, -1, 0), Vec3(0, 1, 0)},
                 {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, -1, 0), Vec3(0, 1, 0)}};
  for (double separation : {0.0, 0.05}) {
    const double contact = (1.0 - separation) / 2.0;
    EXPECT_NEAR(ee_distance(m, contact), separation, 1e-14);
    const double s = ee_fraction(m, separation);
    EXPECT_LE(s, contact);
    EXPECT_GE(s, 0.8 * contact);
    EXPECT_NEAR(s, 0.9 * contact, 1e-12);
  }
}

// Parallel, overlapping edges closing head-on while b also slides along its length: the gap
// 0.6 - 0.8 s reaches d = 0.04 at t* = 0.7 (the closest points form a whole segment here, and l_p
// exceeds the closing speed 0.8 because of the slide).
TEST(AdditiveCcd, ParallelEdgesApproaching) {
  const Motion m{{Vec3(0, 0, 0.3), Vec3(1, 0, 0.3), Vec3(0.5, 0, -0.3), Vec3(1.5, 0, -0.3)},
                 {Vec3(0, 0, -0.1), Vec3(1, 0, -0.1), Vec3(0.7, 0, 0.1), Vec3(1.7, 0, 0.1)}};
  const double separation = 0.04, contact = 0.7;
  EXPECT_NEAR(ee_distance(m, contact), separation, 1e-14);
  const double s = ee_fraction(m, separation);
  EXPECT_LE(s, contact);
  EXPECT_GE(s, 0.8 * contact);
}

TEST(AdditiveCcd, GrazingPastWithoutContactReturnsOne) {
  // The point slides over the triangle's face at constant height 0.2, then past its corner.
  const Motion over{{Vec3(-1, 0.2, 0.2), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                    {Vec3(2, 0.2, 0.2), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  EXPECT_EQ(pt_fraction(over, 0.1), 1.0);
  // The point passes beside the edge y = 0 at 1.12 while starting 1.5 away.
  const Motion beside{{Vec3(-1, -1, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                      {Vec3(2, -1, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  EXPECT_EQ(pt_fraction(beside, 0.1), 1.0);
  // Edge a sweeps sideways over edge b at height 0.3.
  const Motion sweep{{Vec3(-2, -1, 0.3), Vec3(-2, 1, 0.3), Vec3(0, 0, 0), Vec3(1, 0, 0)},
                     {Vec3(3, -1, 0.3), Vec3(3, 1, 0.3), Vec3(0, 0, 0), Vec3(1, 0, 0)}};
  EXPECT_EQ(ee_fraction(sweep, 0.1), 1.0);
}

TEST(AdditiveCcd, StartingWithinTheSeparationReturnsZero) {
  const Motion pt{{Vec3(0.2, 0.2, 0.05), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                  {Vec3(0.2, 0.2, 1.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};  // even moving away
  EXPECT_EQ(pt_fraction(pt, 0.1), 0.0);
  EXPECT_EQ(pt_fraction(pt, 0.05), 0.0);  // exactly at the separation is not above it
  const Motion ee{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 0.02), Vec3(0.5, 1, 0.02)},
                  {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 2.0), Vec3(0.5, 1, 2.0)}};
  EXPECT_EQ(ee_fraction(ee, 0.1), 0.0);
  EXPECT_EQ(ee_fraction(ee, 0.0), 1.0);  // apart and moving away
}

TEST(AdditiveCcd, NoMotionReturnsOneWhenApart) {
  const Motion pt{{Vec3(0.2, 0.2, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                  {Vec3(0.2, 0.2, 0.5), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  EXPECT_EQ(pt_fraction(pt, 0.1), 1.0);
  EXPECT_EQ(pt_fraction(pt, 0.6), 0.0);
  const Motion ee{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 0.5), Vec3(0.5, 1, 0.5)},
                  {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 0.5), Vec3(0.5, 1, 0.5)}};
  EXPECT_EQ(ee_fraction(ee, 0.1), 1.0);
}

TEST(AdditiveCcd, CommonTranslationReturnsOneWhenApart) {
  std::mt19937 rng(11);
  int apart = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Motion m;
    const Vec3 shift = random_vec(rng, 10.0);
    for (int i = 0; i < 4; ++i) {
      m.from[i] = random_vec(rng, 1.0);
      m.to[i] = m.from[i] + shift;
    }
    if (pt_distance(m, 0.0) > 0.05) {
      ++apart;
      EXPECT_EQ(pt_fraction(m, 0.02), 1.0) << trial;
    }
    if (ee_distance(m, 0.0) > 0.05) {
      EXPECT_EQ(ee_fraction(m, 0.02), 1.0) << trial;
    }
  }
  EXPECT_GT(apart, 300);
}

TEST(AdditiveCcd, SwappingTheEdgesGivesTheSameFraction) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 2000; ++trial) {
    Motion m;
    for (int i = 0; i < 4; ++i) {
      m.from[i] = random_vec(rng, 1.0);
      m.to[i] = m.from[i] + random_vec(rng, 1.0);
    }
    const Motion swapped{{m.from[2], m.from[3], m.from[0], m.from[1]}, {m.to[2], m.to[3], m.to[0], m.to[1]}};
    EXPECT_EQ(ee_fraction(m, 0.03), ee_fraction(swapped, 0.03)) << trial;
  }
}

// Vertices in [-1, 1]³ moving by up to 1.5 per coordinate; `aimed`: the first primitive's
// vertices (0..split-1) shifted at the end so that their centroid lands within 0.3 of the
// other's, so that many of these paths meet.
Motion random_motion(std::mt19937& rng, int split, bool aimed) {
  Motion m;
  for (int i = 0; i < 4; ++i) {
    m.from[i] = random_vec(rng, 1.0);
    m.to[i] = m.from[i] + random_vec(rng, 1.5);
  }
  if (aimed) {
    Vec3 first = Vec3::Zero(), second = Vec3::Zero();
    for (int i = 0; i < 4; ++i) (i < split ? first : second) += m.to[i] / (i < split ? split : 4.0 - split);
    const Vec3 shift = second - first + random_vec(rng, 0.3);
    for (int i = 0; i < split; ++i) m.to[i] += shift;
  }
  return m;
}

// Random motions, sampled at N + 1 points of the path (N = kSamples) with the reference distances:
//  * safe: no sample before the returned s is within the separation, and the point at s keeps
//    (1 - η) of the start's gap (the search stops before the gap falls below that);
//  * not needlessly small: the distance is l_p-Lipschitz in s, so between samples 1/N apart it
//    dips at most l_p/(2N) below the smaller sample; where the sampled gap minus that stays above
//    (1 - η) of the start's gap the search never stops, and returns 1 (when its step count bound
//    l_p/(η (1 - η) g0) + 1 is within the cap).
struct RandomMotionCounts {
  int free_paths = 0;
  std::vector<double> contact_ratios;  // s / the first sampled contact, per path with contact
};

RandomMotionCounts check_random_motions(bool point_triangle, unsigned seed) {
  constexpr int kSamples = 2000, kTrials = 1500;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> separation_of(0.0, 0.1);
  const AdditiveCcdParams params;
  const double eta = params.conservative_rescaling;
  RandomMotionCounts counts;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Motion m = random_motion(rng, point_triangle ? 1 : 2, trial % 2 == 1);
    const double separation = separation_of(rng);
    const auto distance = [&](double t) { return point_triangle ? pt_distance(m, t) : ee_distance(m, t); };
    const double s = point_triangle ? pt_fraction(m, separation) : ee_fraction(m, separation);
    EXPECT_TRUE(s >= 0.0 && s <= 1.0) << trial;
    const double g0 = distance(0.0) - separation;
    if (g0 <= 0.0) {
      EXPECT_EQ(s, 0.0) << trial;
      continue;
    }
    double min_gap = g0, first_contact = 1.0;
    for (int k = 0; k <= kSamples; ++k) {
      const double t = static_cast<double>(k) / kSamples, gap = distance(t) - separation;
      if (gap <= 0.0 && min_gap > 0.0) first_contact = t;
      min_gap = std::min(min_gap, gap);
      if (t < s && gap < -1e-12) {
        ADD_FAILURE() << "trial " << trial << ": within the separation at " << t << " before s = " << s;
        break;
      }
    }
    if (s < 1.0) {
      EXPECT_GE(distance(s) - separation, (1.0 - eta) * g0 - 1e-12) << trial;
    }
    if (min_gap <= 0.0) counts.contact_ratios.push_back(s / first_contact);
    const double l_p = lipschitz_bound(m, point_triangle ? 1 : 2);
    const bool within_cap = l_p / (eta * (1.0 - eta) * g0) + 1.0 < params.max_iterations;
    if (within_cap && min_gap - l_p / (2.0 * kSamples) > (1.0 - eta) * g0 + 1e-12) {
      ++counts.free_paths;
      EXPECT_EQ(s, 1.0) << trial;
    }
  }
  return counts;
}

// ACCD's loop as its comments state it (Li et al. 2021, Alg. 1), on the relative motion (the mean
// displacement removed), with no shortcut: the reference for the shortcut that ends a search on
// the primitives' boxes.
double reference_search(const Motion& m, int split, double separation, const AdditiveCcdParams& params) {
  std::array<Vec3, 4> move;
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < 4; ++i) mean += m.to[i] - m.from[i];
  for (int i = 0; i < 4; ++i) move[i] = m.to[i] - m.from[i] - mean / 4.0;
  const auto at = [&](int i, double s) { return Vec3(m.from[i] + s * move[i]); };
  const auto squared = [&](double s) {
    return split == 1 ? point_triangle_squared(at(0, s), at(1, s), at(2, s), at(3, s))
                      : segment_segment_squared(at(0, s), at(1, s), at(2, s), at(3, s));
  };
  const double eta = params.conservative_rescaling, l_p = lipschitz_bound(m, split);
  const auto gap_at = [&](double s) {
    const double d2 = squared(s);
    return (d2 - separation * separation) / (std::sqrt(d2) + separation);
  };
  double gap = gap_at(0.0), s = 0.0;
  if (!(gap > 0.0)) return 0.0;
  if (l_p == 0.0) return 1.0;
  const double stop = (1.0 - eta) * gap;
  for (int step = 0; step < params.max_iterations; ++step) {
    const double next = s + eta * gap / l_p;
    if (next >= 1.0) return 1.0;
    const double next_gap = gap_at(next);
    if (!(next_gap >= stop) && (s > 0.0 || !(next_gap > 0.0))) return s;
    s = next;
    gap = next_gap;
  }
  return s;
}

// Most pairs a step scans are far apart for their motion, and the search ends at once on their
// boxes (where eta (box distance - separation) >= l_p). Over pairs offset by up to a few of their
// sizes and moving by amounts from a thousandth to several of their sizes, both sides of that test
// occur many times, and every fraction is the plain search's.
TEST(AdditiveCcd, TheBoxShortcutReturnsWhatTheSearchWould) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0), exponent(-3.0, 0.7);
  const AdditiveCcdParams params;
  int shortcut = 0, searched = 0, short_of_one = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const int split = trial % 2 == 0 ? 1 : 2;
    const double scale = std::pow(10.0, exponent(rng)), separation = 0.3 * unit(rng);
    const Vec3 offset = random_vec(rng, 1.5);
    Motion m;
    for (int i = 0; i < 4; ++i) {
      m.from[i] = Vec3(unit(rng), unit(rng), unit(rng)) + (i < split ? offset : Vec3::Zero());
      m.to[i] = m.from[i] + random_vec(rng, scale);
    }
    const double box_gap = std::sqrt(split_boxes_squared_distance(m.from, split)) - separation;
    (params.conservative_rescaling * box_gap >= lipschitz_bound(m, split) ? shortcut : searched) += 1;
    const double expected = reference_search(m, split, separation, params);
    short_of_one += expected < 1.0;
    EXPECT_NEAR(split == 1 ? pt_fraction(m, separation) : ee_fraction(m, separation), expected, 1e-9) << trial;
  }
  EXPECT_GT(shortcut, 1000);
  EXPECT_GT(searched, 1000);
  EXPECT_GT(short_of_one, 100);
}

// Close to the contact: head-on, s = η t*; oblique approaches and l_p's overestimate of the
// closing speed cost some, so the median of s over the first sampled contact, over the paths with
// contact, is held above 0.75 (a search stopping needlessly early fails it).
void expect_close_to_contact(std::vector<double> ratios) {
  ASSERT_GT(ratios.size(), 200u);
  std::sort(ratios.begin(), ratios.end());
  EXPECT_GT(ratios[ratios.size() / 2], 0.75);
  EXPECT_LE(ratios.back(), 1.0);
}

TEST(AdditiveCcd, RandomPointTriangleMotionsAreSafeAndNotNeedlesslyShort) {
  const RandomMotionCounts counts = check_random_motions(true, 21);
  EXPECT_GT(counts.free_paths, 200);
  expect_close_to_contact(counts.contact_ratios);
}

TEST(AdditiveCcd, RandomEdgeEdgeMotionsAreSafeAndNotNeedlesslyShort) {
  const RandomMotionCounts counts = check_random_motions(false, 22);
  EXPECT_GT(counts.free_paths, 200);
  expect_close_to_contact(counts.contact_ratios);
}

// With a cap of a few steps on a long approach the search stops early, at a safe s.
TEST(AdditiveCcd, IterationCapReturnsTheSafeFractionReached) {
  const Motion m{{Vec3(0.2, 0.3, 1.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                 {Vec3(5.2, 0.3, 0.1), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
  AdditiveCcdParams capped;
  capped.max_iterations = 3;
  const double s = pt_fraction(m, 0.05, capped);
  EXPECT_GT(s, 0.0);
  EXPECT_LT(s, pt_fraction(m, 0.05));
  for (int k = 0; k <= 1000; ++k) EXPECT_GT(pt_distance(m, s * k / 1000.0), 0.05);
}

// `enough` may stop a search early, never change the minimum over pairs: below it the fraction is
// the full search's bit for bit; otherwise it is at least `enough`. The random aimed motions meet
// at every fraction, so both sides are exercised.
TEST(AdditiveCcd, EnoughStopsTheSearchWithoutChangingAnyFractionBelowIt) {
  std::mt19937 rng(11);
  int below = 0, stopped = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const bool edges = trial % 2 == 1;
    const Motion m = random_motion(rng, edges ? 2 : 1, true);
    const double enough = std::uniform_real_distribution<double>(0.05, 1.0)(rng);
    const auto fraction = [&](double e) {
      return edges ? edge_edge_safe_fraction(m.from[0], m.from[1], m.from[2], m.from[3], m.to[0], m.to[1], m.to[2],
                                             m.to[3], 0.03, {}, e)
                   : point_triangle_safe_fraction(m.from[0], m.from[1], m.from[2], m.from[3], m.to[0], m.to[1],
                                                  m.to[2], m.to[3], 0.03, {}, e);
    };
    const double full = fraction(1.0), early = fraction(enough);
    if (full < enough) {
      ++below;
      EXPECT_EQ(early, full) << trial;
    } else {
      ++stopped;
      EXPECT_GE(early, enough) << trial;
      EXPECT_LE(early, full) << trial;
    }
  }
  EXPECT_GT(below, 400);
  EXPECT_GT(stopped, 400);
}

}  // namespace
}  // namespace fnopt
