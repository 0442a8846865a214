#include <fnopt/contact/additive_ccd.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include <fnopt/contact/box.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

void AdditiveCcdParams::validate() const {
  require(conservative_rescaling > 0.0 && conservative_rescaling < 1.0, "ccd.conservative_rescaling",
          "must lie in (0, 1)");
  require(max_iterations >= 1, "ccd.max_iterations", "must be a positive count");
}

namespace ccd_distance {

double point_segment_squared(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = b - a;
  const double ee = e.squaredNorm();
  if (ee == 0.0) return (p - a).squaredNorm();
  const double t = std::clamp((p - a).dot(e) / ee, 0.0, 1.0);
  return (p - (a + t * e)).squaredNorm();
}

// Where p's projection onto the triangle's plane lies inside the triangle (on the inner side of
// all three edges: ((t_{k+1} - t_k) × (p - t_k)) · n >= 0, n the unnormalised normal) the distance
// is the plane's, ((p - t0) · n)² / |n|²; elsewhere the closest point lies on the boundary, the
// nearest of the three edges. A degenerate triangle (n = 0) is its edges.
double point_triangle_squared(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
  const Vec3 n = (t1 - t0).cross(t2 - t0);
  const double nn = n.squaredNorm();
  if (nn > 0.0 && (t1 - t0).cross(p - t0).dot(n) >= 0.0 && (t2 - t1).cross(p - t1).dot(n) >= 0.0 &&
      (t0 - t2).cross(p - t2).dot(n) >= 0.0) {
    const double height = (p - t0).dot(n);
    return height * height / nn;
  }
  return std::min(
      {point_segment_squared(p, t0, t1), point_segment_squared(p, t1, t2), point_segment_squared(p, t2, t0)});
}

// |a0 + u d_a - b0 - v d_b|² is a convex quadratic on the square (u, v) in [0, 1]². Ericson's
// ClosestPtSegmentSegment (Real-Time Collision Detection, §5.1.9) finds its minimum: the lines'
// closest u, clamped to [0, 1]; the v closest to that point, and where it leaves [0, 1], v clamped
// and u solved again for it. The result is the distance of the two points it names, never less
// than the true one. The normal equations' det = |d_a|²|d_b|² - (d_a · d_b)² = |d_a|²|d_b|² sin²θ;
// where the edges are nearly parallel (sin²θ below kNearlyParallel, degenerate edges included)
// u is ill-conditioned, and the minimum is taken over the candidates that do not need it: the
// four end-to-segment distances, and the lines' closest pair where it lies in the square.
double segment_segment_squared(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  constexpr double kNearlyParallel = 1e-6;
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double aa = da.squaredNorm(), bb = db.squaredNorm(), ab = da.dot(db);
  const double ar = da.dot(r), br = db.dot(r);
  const double det = aa * bb - ab * ab;
  if (det > kNearlyParallel * aa * bb) {
    double u = std::clamp((ab * br - ar * bb) / det, 0.0, 1.0);
    double v = (ab * u + br) / bb;
    if (v < 0.0) {
      v = 0.0;
      u = std::clamp(-ar / aa, 0.0, 1.0);
    } else if (v > 1.0) {
      v = 1.0;
      u = std::clamp((ab - ar) / aa, 0.0, 1.0);
    }
    return (r + u * da - v * db).squaredNorm();
  }
  double best = std::min({point_segment_squared(a0, b0, b1), point_segment_squared(a1, b0, b1),
                          point_segment_squared(b0, a0, a1), point_segment_squared(b1, a0, a1)});
  if (det > 0.0) {
    const double u = (ab * br - ar * bb) / det, v = (aa * br - ab * ar) / det;
    if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) best = std::min(best, (r + u * da - v * db).squaredNorm());
  }
  return best;
}

}  // namespace ccd_distance

namespace {

// Four vertices moving linearly, their common translation removed: vertex i is at
// start[i] + s move[i], move[i] = (end[i] - start[i]) - p̄, p̄ the mean displacement. The
// distances between the primitives are those of the true motion (translated by s p̄).
struct RelativeMotion {
  std::array<Vec3, 4> start, move;

  RelativeMotion(const std::array<Vec3, 4>& from, const std::array<Vec3, 4>& to) : start(from) {
    Vec3 mean = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      move[i] = to[i] - from[i];
      mean += move[i];
    }
    mean /= 4.0;
    for (Vec3& m : move) m -= mean;
  }
  Vec3 at(int i, double s) const { return start[i] + s * move[i]; }
  // The largest |move[i]| over vertices first..last (one primitive).
  double largest_move(int first, int last) const {
    double largest = 0.0;
    for (int i = first; i <= last; ++i) largest = std::max(largest, move[i].squaredNorm());
    return std::sqrt(largest);
  }
};

// ACCD's loop (Li et al. 2021, Alg. 1) on the squared distance d²(s) of the relative motion, whose
// distance is l_p-Lipschitz in s. With ξ the separation and the gap g(s) = (d² - ξ²)/(d + ξ)
// (= d - ξ), each step is Δs = η g(s)/l_p: the path stays at least ξ + (1 - η) g(s) away over it.
// The first step is always taken (its end keeps (1 - η) g(0) in exact arithmetic); after it the
// loop stops, returning the last s reached, as soon as the next s's gap falls below
// (1 - η) g(0). A step reaching s = 1 proves the whole move safe; one reaching `enough` ends the
// search there (additive_ccd.hpp).
template <class SquaredDistance>
double additive_ccd(const SquaredDistance& distance_squared, double l_p, double separation,
                    const AdditiveCcdParams& params, double enough) {
  assert(separation >= 0.0);
  const double eta = params.conservative_rescaling;
  const double xi_sq = separation * separation;
  const double d_sq = distance_squared(0.0);
  if (!(d_sq > xi_sq)) return 0.0;  // within the separation at the start (or not a number)
  if (l_p == 0.0) return 1.0;       // a common translation: no distance changes
  if (!std::isfinite(l_p) || !std::isfinite(d_sq)) return 0.0;
  const auto gap_at = [&](double s) {
    const double d2 = distance_squared(s);
    return (d2 - xi_sq) / (std::sqrt(d2) + separation);
  };
  double gap = (d_sq - xi_sq) / (std::sqrt(d_sq) + separation);
  const double stop_gap = (1.0 - eta) * gap;
  double s = 0.0;
  for (int step = 0; step < params.max_iterations; ++step) {
    const double next = s + eta * gap / l_p;
    if (next >= 1.0) return 1.0;
    const double next_gap = gap_at(next);
    if (!(next_gap >= stop_gap) && (s > 0.0 || !(next_gap > 0.0))) return s;
    s = next;
    if (s >= enough) return s;
    gap = next_gap;
  }
  return s;  // the cap: safe up to here
}

// Whether ACCD's first step already reaches s = 1 (the whole move safe), decided on the boxes of
// the two primitives' start positions (vertices 0 .. split - 1 and split .. 3) instead of their
// exact distance d(0): the boxes' distance bounds d(0) from below, so where
// eta (box distance - separation) >= l_p, the first step eta g(0) / l_p is 1 or more too. Most
// candidate pairs of a step end there, without their exact distance. The margins (box.hpp's on the
// distance, relative on l_p) keep the decision on the side of the exact one's rounding (and of the
// l_p the loop computes in its own vertex order): where this says 1, so does the loop.
bool first_step_reaches_end(const std::array<Vec3, 4>& start, int split, double l_p, double separation,
                            double eta) {
  for (const Vec3& p : start)
    if (!p.allFinite()) return false;
  return eta * (std::sqrt(split_boxes_squared_distance(start, split)) - separation - kBoxRoundingMargin) >=
         l_p * (1.0 + 1e-9);
}

}  // namespace

double point_triangle_safe_fraction(const Vec3& p0_start, const Vec3& t0_start, const Vec3& t1_start,
                                    const Vec3& t2_start, const Vec3& p0_end, const Vec3& t0_end, const Vec3& t1_end,
                                    const Vec3& t2_end, double separation, const AdditiveCcdParams& params,
                                    double enough) {
  const RelativeMotion motion({p0_start, t0_start, t1_start, t2_start}, {p0_end, t0_end, t1_end, t2_end});
  // l_p = |p_p| + max_j |p_tj|: the point moves by the first, any point of the triangle, a convex
  // combination of its corners, by at most the second.
  const double l_p = motion.largest_move(0, 0) + motion.largest_move(1, 3);
  if (first_step_reaches_end(motion.start, 1, l_p, separation, params.conservative_rescaling)) return 1.0;
  const auto distance_squared = [&motion](double s) {
    return ccd_distance::point_triangle_squared(motion.at(0, s), motion.at(1, s), motion.at(2, s), motion.at(3, s));
  };
  return additive_ccd(distance_squared, l_p, separation, params, enough);
}

double edge_edge_safe_fraction(const Vec3& ea0_start, const Vec3& ea1_start, const Vec3& eb0_start,
                               const Vec3& eb1_start, const Vec3& ea0_end, const Vec3& ea1_end, const Vec3& eb0_end,
                               const Vec3& eb1_end, double separation, const AdditiveCcdParams& params,
                               double enough) {
  const RelativeMotion given({ea0_start, ea1_start, eb0_start, eb1_start}, {ea0_end, ea1_end, eb0_end, eb1_end});
  if (first_step_reaches_end(given.start, 2, given.largest_move(0, 1) + given.largest_move(2, 3), separation,
                             params.conservative_rescaling))
    return 1.0;
  // The two edges in a canonical order (the lexicographically smaller motion, start then end
  // coordinates, first), so that swapping them runs the same arithmetic and returns the same s.
  std::array<double, 12> a, b;
  const std::array<const Vec3*, 4> a_parts{&ea0_start, &ea1_start, &ea0_end, &ea1_end};
  const std::array<const Vec3*, 4> b_parts{&eb0_start, &eb1_start, &eb0_end, &eb1_end};
  for (int k = 0; k < 4; ++k) {
    for (int c = 0; c < 3; ++c) {
      a[3 * k + c] = (*a_parts[k])(c);
      b[3 * k + c] = (*b_parts[k])(c);
    }
  }
  const bool swap = std::lexicographical_compare(b.begin(), b.end(), a.begin(), a.end());
  const RelativeMotion motion =
      swap ? RelativeMotion({eb0_start, eb1_start, ea0_start, ea1_start}, {eb0_end, eb1_end, ea0_end, ea1_end})
           : RelativeMotion({ea0_start, ea1_start, eb0_start, eb1_start}, {ea0_end, ea1_end, eb0_end, eb1_end});
  // l_p = max_i |p_ai| + max_j |p_bj|: a point of either segment moves by at most its ends' largest.
  const double l_p = motion.largest_move(0, 1) + motion.largest_move(2, 3);
  const auto distance_squared = [&motion](double s) {
    return ccd_distance::segment_segment_squared(motion.at(0, s), motion.at(1, s), motion.at(2, s), motion.at(3, s));
  };
  return additive_ccd(distance_squared, l_p, separation, params, enough);
}

}  // namespace fnopt
