#pragma once
// The absolute-value projection (psd_projection.hpp) of an angle spring's 6x6 Hessian in (u, w), in
// closed form: the same matrix as project_psd<6>, without a numerical eigen-decomposition, which
// was most of a projected stencil Hessian's cost (docs/design.md §6).
//
// E = K/2 delta^2, delta = theta - theta0:  hess E = K (grad theta grad theta^T + delta hess theta).
// In the orthonormal frame of the plane of u and w (n = u^ x w^ / sin theta, t_u = n x u^,
// t_w = n x w^; a = 1/|u|, b = 1/|w|), theta is the angle of w minus the angle of u in that plane
// and even in the normal components, so the Hessian splits into (in units of K)
//   in-plane, on (u.u^, u.t_u, w.w^, w.t_w):  [[0, delta a^2, 0, 0], [delta a^2, a^2, 0, -ab],
//                                              [0, 0, 0, -delta b^2], [0, -ab, -delta b^2, b^2]]
//   normal, on (u.n, w.n):                     delta / sin theta [[a^2 cos theta, -ab], [-ab, b^2 cos theta]]
// (polar coordinates: d2(angle)/dr dt = -1/r^2 and the angle is linear in t; the normal block from
// cos theta' = (u.w + e_u e_w) / (|u'| |w'|)). With A = a^2, B = b^2 the in-plane block's
// characteristic polynomial is
//   q(l) = l^4 - (A+B) l^3 - delta^2 (A^2+B^2) l^2 + delta^2 AB (A+B) l + delta^4 A^2 B^2;
// q(0) = det > 0, the trace is positive and the (u^, t_u) minor indefinite, so exactly two roots are
// negative: one below and one above both of r_u, r_w, the negative roots of l^2 - A l - delta^2 A^2
// and of l^2 - B l - delta^2 B^2, where q = -AB l^2 < 0. The normal block has one negative
// eigenvalue (its determinant is -delta^2 AB < 0). The projection adds 2 K |l| z z^T for each.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace fnopt {

namespace angle_projection_detail {

// The in-plane block's eigenvalues l != 0 are the roots of F(l) = f_u(l) f_w(l) - AB, with
// f_u(l) = l - A - delta^2 A^2 / l (its rows of u.u^ and w.w^ eliminated; q(l) = l^2 F(l)). In this
// product form F loses no digits to cancellation before its last subtraction.
struct InPlaneSecular {
  double A, B, d2;
  void evaluate(double l, double& value, double& slope) const {
    const double inverse = 1.0 / l, pu = d2 * A * A * inverse, pw = d2 * B * B * inverse;
    const double fu = l - A - pu, fw = l - B - pw;
    value = fu * fw - A * B;
    slope = (1.0 + pu * inverse) * fw + fu * (1.0 + pw * inverse);
  }
};

// The root of F in (lo, hi), where F(lo) > 0 > F(hi) or F(lo) < 0 < F(hi): Newton's method from x,
// bisecting where a step would leave the bracket.
inline double bracketed_root(const InPlaneSecular& F, double lo, double hi, double x) {
  double value = 0.0, slope = 0.0;
  F.evaluate(lo, value, slope);
  const bool positive_at_lo = value > 0.0;
  if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < 100; ++iteration) {
    F.evaluate(x, value, slope);
    if (value == 0.0) return x;
    ((value > 0.0) == positive_at_lo ? lo : hi) = x;
    const double next = x - value / slope;
    if (std::abs(next - x) <= 1e-13 * std::abs(x)) return next;
    x = next > lo && next < hi ? next : 0.5 * (lo + hi);
  }
  return x;
}

}  // namespace angle_projection_detail

// Huw: the exact Hessian of E = K/2 (theta - theta0)^2 in (u, w) at edges u and w, delta = theta -
// theta0. Replaces its negative eigenvalues by their absolute values. Returns false, Huw unchanged,
// where u and w are (nearly) parallel but delta is not small (a collapsed shear corner, a hinge
// folded flat): the plane's normal, computed from u x w, is then too uncertain for eigenvalues of
// order K delta / sin theta, and the caller projects numerically. (A nearly flat hinge, delta ~ theta,
// keeps the closed form: n is uncertain by 1e-16 / theta, its eigenvalues are of order K theta.)
inline bool project_angle_hessian(const Eigen::Vector3d& u, const Eigen::Vector3d& w, double stiffness, double delta,
                                  Eigen::Matrix<double, 6, 6>& Huw) {
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  const double a = 1.0 / u.norm(), b = 1.0 / w.norm();
  const Eigen::Vector3d uh = a * u, wh = b * w;
  const Eigen::Vector3d cross = uh.cross(wh);
  const double sin = cross.norm(), cos = uh.dot(wh);
  if (stiffness <= 0.0 || delta == 0.0) return true;
  if (sin == 0.0 || (sin < 1e-6 && std::abs(delta) > 1e-3)) return false;
  const Eigen::Vector3d n = cross / sin, tu = n.cross(uh), tw = n.cross(wh);
  auto add = [&](double eigenvalue, const Vec6& z) {
    Huw.noalias() += (2.0 * stiffness * -eigenvalue) * z * z.transpose();
  };

  // The normal block's negative eigenpair: [[x, y], [y, z]], det < 0.
  {
    const double s = delta / sin;
    const double x = s * cos * a * a, y = -s * a * b, z = s * cos * b * b;
    const double mean = 0.5 * (x + z), radius = std::sqrt(0.25 * (x - z) * (x - z) + y * y);
    // The eigenvalue of the smaller magnitude without cancellation: det / (mean + radius) where mean > 0.
    const double low = mean > 0.0 ? (x * z - y * y) / (mean + radius) : mean - radius;
    Eigen::Vector2d v1(y, low - x), v2(low - z, y);
    const Eigen::Vector2d v = (v1.squaredNorm() >= v2.squaredNorm() ? v1 : v2).normalized();
    Vec6 e;
    e << v[0] * n, v[1] * n;
    add(low, e);
  }

  // The in-plane block's two negative eigenpairs.
  const double A = a * a, B = b * b, d2 = delta * delta;
  const angle_projection_detail::InPlaneSecular q{A, B, d2};
  const double root_factor = 2.0 * d2 / (1.0 + std::sqrt(1.0 + 4.0 * d2));  // -r_u / A = -r_w / B
  const double r_low = -root_factor * std::max(A, B), r_high = -root_factor * std::min(A, B);
  // Below Gershgorin's lower bound of the block's spectrum, where F > 0.
  const double ad = std::abs(delta);
  const double floor = 1.01 * std::min({-ad * A, A - ad * A - a * b, -ad * B, B - a * b - ad * B});
  const double roots[2] = {
      angle_projection_detail::bracketed_root(q, floor, r_low, -ad * a * b),
      angle_projection_detail::bracketed_root(q, r_high, 0.0,
                                              -2.0 * d2 * A * B / ((A + B) * (1.0 + std::sqrt(1.0 + d2)))),
  };
  for (const double l : roots) {
    // (M - l I) v = 0 from the rows of u.u^, u.t_u and w.w^ (M's entries as above).
    const double x3 = d2 * A * A + A * l - l * l;
    const Eigen::Vector4d v = Eigen::Vector4d(delta * A * a * b, a * b * l, -delta * B * x3 / l, x3).normalized();
    Vec6 e;
    e << v[0] * uh + v[1] * tu, v[2] * wh + v[3] * tw;
    add(l, e);
  }
  return true;
}

}  // namespace fnopt
