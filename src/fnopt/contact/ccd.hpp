#pragma once
// Continuous collision detection of one vertex against one analytic obstacle (docs/design.md §14).
// Over a step the vertex moves straight from p0 to p1 while the obstacle translates linearly
// from offset o0 to o1 (its poses at the step's two ends, obstacle.hpp). In the obstacle's frame
// the vertex then moves straight too:
//   r(s) = (p0 - o0) + s ((p1 - p0) - (o1 - o0)),   s in [0, 1].
// safe_fraction returns the largest s in [0, 1] such that the distance d(r(s')) stays above the
// separation (the contact thickness) for every s' < s: 0 where it starts within the separation,
// 1 where it never comes within it. Every point of the path before the returned s is outside.
//  * plane: d(r(s)) is linear in s, one division;
//  * sphere: |r(s) - c| = R + separation, the smaller root of a quadratic;
//  * capsule: the union of two end spheres and a cylinder, so the first contact is the earliest of
//    the spheres' roots and the infinite cylinder's entry root where the closest point of the axis
//    lies between the ends (entry through an end disc passes through its sphere first);
//  * rounded box: conservative advancement on its 1-Lipschitz distance (Mirtich 1996): from s
//    with gap d(r(s)) - separation = g > 0 no point of the path comes within the separation
//    before s + g/|r'|, so s advances by that until the gap is below a tolerance; the result never
//    exceeds the exact one.
#include <fnopt/contact/obstacle.hpp>

namespace fnopt {

double safe_fraction(const Obstacle& obstacle, const Vec3& p0, const Vec3& p1, const Vec3& offset0,
                     const Vec3& offset1, double separation);

}  // namespace fnopt
