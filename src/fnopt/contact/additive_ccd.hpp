#pragma once
// Continuous collision detection between two cloth primitives, for self-contact (docs/design.md
// §14): a point and a triangle, or two edges, each vertex moving on a straight line from its
// start to its end over the move, s in [0, 1]. The result has the contract of ccd.hpp's
// safe_fraction: the largest s found such that the distance between the primitives stays above
// `separation` (the contact thickness) for every s' < s; 0 where they start within it, 1 where
// they never come within it. Every point of the path before the returned s is outside; the
// returned s never exceeds the true first time of contact.
//
// The method is additive CCD (ACCD: Li, Kaufman, Jiang et al. 2021, "Codimensional Incremental
// Potential Contact", §5 and Alg. 1; ipc-toolkit's additive_ccd). Distances do not change under a
// common translation, so the mean displacement p̄ of the four vertices is subtracted first; then
// every point of either primitive moves at most
//     l_p = max_i |p_i - p̄| + max_j |p_j - p̄|      (i over one primitive's vertices, j the other's)
// per unit of s, and the distance d(s) is l_p-Lipschitz in s. From s with gap d(s) - ξ > 0
// (ξ the separation) no point of the path comes within ξ before s + (d(s) - ξ)/l_p, so s may
// advance by η (d(s)² - ξ²)/((d(s) + ξ) l_p) (= η (d - ξ)/l_p, written on the squared distance
// that the kernels compute), η < 1 the conservative rescaling. The loop stops before the step
// after which the gap falls below (1 - η) of the start's, so the result keeps that much of the
// start's gap: the first contact lies later, and a head-on approach at constant relative velocity
// returns η of its exact time. Not a root finder: a path that only comes close (within (1 - η) of
// the start's gap, without contact) also stops it early.
//
// `enough`: a caller that keeps only the smallest s over many pairs passes the smallest found so
// far; the search then stops once its s reaches `enough` and returns that s, which cannot lower
// the minimum. An s below `enough` is the one the full search returns, bit for bit (the loop is the
// same up to it), so the minimum over the pairs does not change, and a long move whose first
// contact is already bounded by another pair costs a few steps instead of thousands.
//
// Both functions expect a params that passed validate(), separation >= 0 and enough in (0, 1].
#include <fnopt/util/types.hpp>

namespace fnopt {

struct AdditiveCcdParams {
  // η in (0, 1): each step advances η of the largest step the Lipschitz bound allows, and the
  // search stops where the gap d - ξ would fall below (1 - η) of its value at s = 0. It is
  // ipc-toolkit's conservative_rescaling; the paper's scaling s (its Alg. 1, lines 6 and 8) is
  // 1 - η. Larger η gets closer to the first contact (η of it head-on) with a smaller gap kept.
  double conservative_rescaling = 0.9;
  // Cap on the steps (one distance evaluation each). Every step before the stop advances at least
  // η (1 - η) g0/l_p (g0 the start's gap), so a search needs at most l_p/(η (1 - η) g0) + 1 steps;
  // the cap binds only on moves of thousands of start gaps. Where it binds the s reached is
  // returned: safe, but short of the contact.
  int max_iterations = 100000;

  // Throws Error("ccd.<field>", ...) naming the bad field.
  void validate() const;
};

// The point p moving from p0_start to p0_end, the triangle (t0, t1, t2) from its start corners to
// its end corners.
double point_triangle_safe_fraction(const Vec3& p0_start, const Vec3& t0_start, const Vec3& t1_start,
                                    const Vec3& t2_start, const Vec3& p0_end, const Vec3& t0_end, const Vec3& t1_end,
                                    const Vec3& t2_end, double separation, const AdditiveCcdParams& params = {},
                                    double enough = 1.0);

// Edge a = (ea0, ea1) and edge b = (eb0, eb1). Symmetric: swapping a and b returns the same s, bit
// for bit.
double edge_edge_safe_fraction(const Vec3& ea0_start, const Vec3& ea1_start, const Vec3& eb0_start,
                               const Vec3& eb1_start, const Vec3& ea0_end, const Vec3& ea1_end, const Vec3& eb0_end,
                               const Vec3& eb1_end, double separation, const AdditiveCcdParams& params = {},
                               double enough = 1.0);

// The unsigned distances ACCD evaluates: closed primitives, no derivatives (the barrier's
// differentiable distances are separate). Exposed for tests.
namespace ccd_distance {

// Squared distance between the point p and the closed segment [a, b] (a point where a = b).
double point_segment_squared(const Vec3& p, const Vec3& a, const Vec3& b);
// Squared distance between p and the closed triangle (t0, t1, t2), degenerate ones included.
double point_triangle_squared(const Vec3& p, const Vec3& t0, const Vec3& t1, const Vec3& t2);
// Squared distance between the closed segments [a0, a1] and [b0, b1], parallel ones included.
double segment_segment_squared(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace ccd_distance

}  // namespace fnopt
