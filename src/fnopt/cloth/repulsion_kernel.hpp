#pragma once
// Self-repulsion between two non-adjacent vertices (docs/design.md §2): with d = |x1 - x0| and the
// range delta (default h),
//   b(d) = -lambda (d - delta)^2 log(d / delta)   for d < delta,   0 for d >= delta.
// With s = d/delta and u = d - delta (< 0 inside the range):
//   b'(d)  = -lambda [2u log(s) + u^2/d]                       (< 0: repulsive)
//   b''(d) = -lambda [2 log(s) + 4u/d - u^2/d^2]               (> 0 for d < delta)
// b, b' and b'' all vanish at d = delta, so the barrier is C^2 there (b''' = -6 lambda/delta
// jumps): Newton sees a continuous Hessian as a pair enters the range. b -> +inf as d -> 0.
// Hessian w.r.t. e = x1 - x0, n = e/d:  b'' n n^T + (b'/d)(I - n n^T). The transverse
// eigenvalue b'/d is negative inside the range; the projection (as in stretch_kernel.hpp and
// psd_projection.hpp) replaces it by its absolute value, in closed form.
// lambda is in N/m (J/m^2), like a stretch stiffness: a pair's energy scales as lambda h^2 and
// the pair count per area as 1/h^2, so a fixed lambda is the same surface pressure at every
// resolution (see repulsion_term.hpp for the default).
#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace fnopt {

struct RepulsionKernel {
  static constexpr int kVertices = 2;
  using Vec = Eigen::Matrix<double, 6, 1>;
  using Mat = Eigen::Matrix<double, 6, 6>;

  double stiffness = 0.0;  // lambda [N/m]
  double range = 0.0;      // delta [m]

  // b(d) alone, for metrics and tests.
  double barrier(double d) const {
    if (d >= range) return 0.0;
    if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
    const double u = d - range;
    return -stiffness * u * u * std::log(d / range);
  }
  // b'(d) and b''(d) inside the range (d < delta).
  double barrier_derivative(double d) const {
    const double u = d - range;
    return -stiffness * (2.0 * u * std::log(d / range) + u * u / d);
  }
  double barrier_second_derivative(double d) const {
    const double u = d - range;
    return -stiffness * (2.0 * std::log(d / range) + 4.0 * u / d - u * u / (d * d));
  }

  // True if the pair is inside the range (a non-zero contribution).
  bool active(const Vec& x) const { return (x.tail<3>() - x.head<3>()).squaredNorm() < range * range; }

  double energy(const Vec& x) const { return barrier((x.tail<3>() - x.head<3>()).norm()); }

  double gradient(const Vec& x, Vec& g) const {
    const Eigen::Vector3d e = x.tail<3>() - x.head<3>();
    const double d = e.norm();
    if (d >= range) {
      g.setZero();
      return 0.0;
    }
    const Eigen::Vector3d ge = barrier_derivative(d) / d * e;
    g << -ge, ge;
    return barrier(d);
  }

  void hessian(const Vec& x, Mat& H, bool project) const {
    const Eigen::Vector3d e = x.tail<3>() - x.head<3>();
    const double d = e.norm();
    if (d >= range) {
      H.setZero();
      return;
    }
    const Eigen::Matrix3d axial = e * e.transpose() / (d * d);
    const double along = barrier_second_derivative(d);  // >= 0 inside the range
    double transverse = barrier_derivative(d) / d;      // <= 0 inside the range
    if (project && transverse < 0.0) transverse = -transverse;
    const Eigen::Matrix3d He = along * axial + transverse * (Eigen::Matrix3d::Identity() - axial);
    H << He, -He, -He, He;
  }
};

}  // namespace fnopt
