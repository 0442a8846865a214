#pragma once
// Exact orientation predicates on doubles (Shewchuk 1997, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates"), for the intersection counts of
// mesh_intersections.hpp. They share no code with the contact barrier or its CCD: they are the
// independent referee of what those guarantee.
//
// Each sign is the sign of the exact determinant of the inputs as given (every double is a
// rational number), never of a rounded one. Three stages, the first that can decide does:
//  1. a floating-point filter: the determinant in doubles and Shewchuk's static bound on its
//     rounding error relative to the permanent (the same expression with every product and
//     difference replaced by its absolute value): errbound = (7 + 56 eps) eps permanent for
//     orient3d, (3 + 16 eps) eps |..| for orient2d, eps = 2^-53. If |det| exceeds it, det's sign
//     is exact;
//  2. exact arithmetic on floating-point expansions (sums of non-overlapping doubles, Shewchuk
//     §2): each difference is two doubles (two_sum), products are expanded exactly (two_product
//     by std::fma, scale-expansion), the sum grows exactly (grow-expansion), and the sign is the
//     sign of the largest component;
//  3. for inputs whose binary exponents are too far apart for (1) and (2) to be free of
//     overflow and underflow (more than 2^500 between the largest and the smallest non-zero
//     coordinate, impossible for coordinates converted from float), the same determinant in
//     arbitrary-precision integers: every coordinate is an integer times 2^e0 for the smallest
//     exponent e0, and the sign of a polynomial that is homogeneous in the coordinates does not
//     depend on the common factor.
// Stages (1) and (2) assume no overflow or underflow, which holds when every non-zero coordinate
// lies in [2^-250, 2^251): then all coordinates are multiples of 2^-302, every product of three
// of them a multiple of 2^-906 (a normal double) and smaller than 2^760. Inputs outside that
// range whose exponents span at most 500 are first scaled by a power of two into it (exact, and
// the determinants are homogeneous: the sign is unchanged).
//
// Inputs must be finite (asserted; the callers check their data).
#include <Eigen/Core>

#include <fnopt/util/types.hpp>

namespace fnopt {

// The sign (-1, 0, +1) of det[b - a, c - a, d - a] = (b - a) . ((c - a) x (d - a)): +1 when d
// lies on the side of the plane abc that the normal (b - a) x (c - a) points to (above it when
// a, b, c run counter-clockwise seen from above), 0 when the four points are coplanar.
// (Shewchuk's orient3d(a, b, c, d) has the opposite sign.)
int orient3d_sign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The sign of det[b - a, c - a] = (b - a)_x (c - a)_y - (b - a)_y (c - a)_x: +1 when a, b, c
// run counter-clockwise, 0 when they are collinear (Shewchuk's orient2d's sign).
int orient2d_sign(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);

}  // namespace fnopt
