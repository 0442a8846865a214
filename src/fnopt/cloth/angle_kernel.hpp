#pragma once
// Angle springs on three vertices (docs/design.md §2): E = (K/2) (theta - theta0)^2, theta the angle
// between two edge vectors u and w that are fixed linear combinations of the stencil's vertices.
//   shear, per quad corner (c; a, b):  u = x_a - x_c, w = x_b - x_c, K = k_sh h^2/4, theta0 = pi/2
//   bend, per hinge (p, q, r):         u = x_q - x_p, w = x_r - x_q, K = k_b,        theta0 = 0
// E is written as g(c) with c = cos(theta) = u.w / (|u||w|), so that
//   grad E = g'(c) grad c,   hess E = g''(c) grad c grad c^T + g'(c) hess c,
// where (u^ = u/|u|, w^ = w/|w|)
//   dc/du = (w^ - c u^)/|u|,                 dc/dw = (u^ - c w^)/|w|,
//   d2c/du2  = (3c u^u^T - (w^u^T + u^w^T) - c I)/|u|^2,
//   d2c/dw2  = (3c w^w^T - (u^w^T + w^u^T) - c I)/|w|^2,
//   d2c/dudw = (I - u^u^T - w^w^T + c u^w^T)/(|u||w|).
// With theta0 = 0 (bending) g'(c) = -K theta/sin(theta) and g''(c) = K (sin - theta cos)/sin^3
// are 0/0 at the flat rest state; their Taylor series (1 + theta^2/6, 1/3 + 2 theta^2/15) are used
// below theta = 1e-3. theta = atan2(|u x w|, u.w) keeps precision near 0 and pi.
// The PSD projection acts on the 6x6 Hessian in (u, w), in closed form (angle_projection.hpp);
// mapped back to the 9 vertex coordinates it stays PSD.
#include <Eigen/Core>

#include <fnopt/cloth/angle_projection.hpp>
#include <fnopt/cloth/psd_projection.hpp>

namespace fnopt {

struct AngleKernel {
  static constexpr int kVertices = 3;
  using Vec = Eigen::Matrix<double, 9, 1>;
  using Mat = Eigen::Matrix<double, 9, 9>;

  double stiffness = 0.0;            // K
  double rest_angle = 0.0;           // theta0 [rad]
  Eigen::Vector3d u_coeff{0, 0, 0};  // u = sum_i u_coeff[i] x_i
  Eigen::Vector3d w_coeff{0, 0, 0};  // w = sum_i w_coeff[i] x_i

  static AngleKernel shear(double shear_stiffness, double spacing) {
    return {shear_stiffness * spacing * spacing / 4.0, 1.5707963267948966, {-1, 1, 0}, {-1, 0, 1}};
  }
  static AngleKernel bend(double bend_stiffness) { return {bend_stiffness, 0.0, {-1, 1, 0}, {0, -1, 1}}; }

  double energy(const Vec& x) const {
    const double d = angle(edge(x, u_coeff), edge(x, w_coeff)) - rest_angle;
    return 0.5 * stiffness * d * d;
  }

  double gradient(const Vec& x, Vec& g) const {
    const Eigen::Vector3d u = edge(x, u_coeff), w = edge(x, w_coeff);
    const Local l = local(u, w);
    const Eigen::Vector3d gu = l.dE_dc * l.dc_du, gw = l.dE_dc * l.dc_dw;
    for (int i = 0; i < 3; ++i) g.segment<3>(3 * i) = u_coeff[i] * gu + w_coeff[i] * gw;
    return 0.5 * stiffness * l.delta * l.delta;
  }

  void hessian(const Vec& x, Mat& H, bool project) const {
    const Eigen::Vector3d u = edge(x, u_coeff), w = edge(x, w_coeff);
    const Local l = local(u, w);
    const double nu = u.norm(), nw = w.norm(), c = l.cos;
    const Eigen::Vector3d uh = u / nu, wh = w / nw;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d mixed = wh * uh.transpose() + uh * wh.transpose();
    Eigen::Matrix<double, 6, 1> dc;
    dc << l.dc_du, l.dc_dw;
    Eigen::Matrix<double, 6, 6> Huw = l.d2E_dc2 * dc * dc.transpose();
    Huw.topLeftCorner<3, 3>() += l.dE_dc * (3 * c * uh * uh.transpose() - mixed - c * I) / (nu * nu);
    Huw.bottomRightCorner<3, 3>() += l.dE_dc * (3 * c * wh * wh.transpose() - mixed - c * I) / (nw * nw);
    const Eigen::Matrix3d cross =
        l.dE_dc * (I - uh * uh.transpose() - wh * wh.transpose() + c * uh * wh.transpose()) / (nu * nw);
    Huw.topRightCorner<3, 3>() += cross;
    Huw.bottomLeftCorner<3, 3>() += cross.transpose();
    if (project && !project_angle_hessian(u, w, stiffness, l.delta, Huw)) Huw = project_psd<6>(Huw);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        H.block<3, 3>(3 * i, 3 * j) = u_coeff[i] * u_coeff[j] * Huw.topLeftCorner<3, 3>() +
                                      u_coeff[i] * w_coeff[j] * Huw.topRightCorner<3, 3>() +
                                      w_coeff[i] * u_coeff[j] * Huw.bottomLeftCorner<3, 3>() +
                                      w_coeff[i] * w_coeff[j] * Huw.bottomRightCorner<3, 3>();
  }

 private:
  struct Local {
    double cos, delta, dE_dc, d2E_dc2;
    Eigen::Vector3d dc_du, dc_dw;
  };

  static Eigen::Vector3d edge(const Vec& x, const Eigen::Vector3d& coeff) {
    return coeff[0] * x.segment<3>(0) + coeff[1] * x.segment<3>(3) + coeff[2] * x.segment<3>(6);
  }

  static double angle(const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
    return std::atan2(u.cross(w).norm(), u.dot(w));
  }

  Local local(const Eigen::Vector3d& u, const Eigen::Vector3d& w) const {
    const double nu = u.norm(), nw = w.norm();
    const double sin = u.cross(w).norm() / (nu * nw);
    const double cos = u.dot(w) / (nu * nw);
    const double theta = std::atan2(sin, cos);
    Local l;
    l.cos = cos;
    l.delta = theta - rest_angle;
    const Eigen::Vector3d uh = u / nu, wh = w / nw;
    l.dc_du = (wh - cos * uh) / nu;
    l.dc_dw = (uh - cos * wh) / nw;
    if (rest_angle == 0.0 && theta < 1e-3) {
      const double t2 = theta * theta;
      l.dE_dc = -stiffness * (1.0 + t2 / 6.0);
      l.d2E_dc2 = stiffness * (1.0 / 3.0 + 2.0 * t2 / 15.0);
    } else {
      const double s = std::max(sin, 1e-12);
      l.dE_dc = -stiffness * l.delta / s;
      l.d2E_dc2 = stiffness * (1.0 / (s * s) - l.delta * cos / (s * s * s));
    }
    return l;
  }
};

}  // namespace fnopt
