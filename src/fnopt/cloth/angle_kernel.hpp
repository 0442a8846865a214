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
  // The coefficients of shear() (Corner) and bend() (Hinge), for which the 9x9 Hessian is sums of
  // the 6x6's blocks: the values of General's products with the coefficients (+-1 and 0 are exact),
  // for about a third of the flops.
  enum class Layout { General, Corner, Hinge };
  Layout layout = Layout::General;

  static AngleKernel shear(double shear_stiffness, double spacing) {
    return {shear_stiffness * spacing * spacing / 4.0, 1.5707963267948966, {-1, 1, 0}, {-1, 0, 1}, Layout::Corner};
  }
  static AngleKernel bend(double bend_stiffness) {
    return {bend_stiffness, 0.0, {-1, 1, 0}, {0, -1, 1}, Layout::Hinge};
  }

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
    Eigen::Matrix<double, 6, 6> Huw = edge_hessian(l);
    if (project) project_edge_hessian(u, w, l, Huw);
    to_vertices(Huw, H);
  }

  // hessian(x, exact, false) and hessian(x, projected, true) from one evaluation.
  void hessian_pair(const Vec& x, Mat& exact, Mat& projected) const {
    const Eigen::Vector3d u = edge(x, u_coeff), w = edge(x, w_coeff);
    const Local l = local(u, w);
    Eigen::Matrix<double, 6, 6> Huw = edge_hessian(l);
    to_vertices(Huw, exact);
    project_edge_hessian(u, w, l, Huw);
    to_vertices(Huw, projected);
  }

 private:
  struct Local {
    double cos, delta, dE_dc, d2E_dc2, inv_u, inv_w;
    Eigen::Vector3d uh, wh, dc_du, dc_dw;
  };

  // The Hessian in (u, w).
  Eigen::Matrix<double, 6, 6> edge_hessian(const Local& l) const {
    const double c = l.cos;
    const Eigen::Vector3d& uh = l.uh;
    const Eigen::Vector3d& wh = l.wh;
    const double ku = l.dE_dc * l.inv_u * l.inv_u, kw = l.dE_dc * l.inv_w * l.inv_w, kuw = l.dE_dc * l.inv_u * l.inv_w;
    Eigen::Matrix<double, 6, 6> Huw;
    for (int q = 0; q < 3; ++q)
      for (int p = 0; p < 3; ++p) {
        const double id = p == q ? 1.0 : 0.0;
        Huw(p, q) = l.d2E_dc2 * l.dc_du[p] * l.dc_du[q] +
                    ku * (3.0 * c * uh[p] * uh[q] - wh[p] * uh[q] - uh[p] * wh[q] - c * id);
        Huw(3 + p, 3 + q) = l.d2E_dc2 * l.dc_dw[p] * l.dc_dw[q] +
                            kw * (3.0 * c * wh[p] * wh[q] - uh[p] * wh[q] - wh[p] * uh[q] - c * id);
        const double cross =
            l.d2E_dc2 * l.dc_du[p] * l.dc_dw[q] + kuw * (id - uh[p] * uh[q] - wh[p] * wh[q] + c * uh[p] * wh[q]);
        Huw(p, 3 + q) = cross;
        Huw(3 + q, p) = cross;
      }
    return Huw;
  }

  void project_edge_hessian(const Eigen::Vector3d& u, const Eigen::Vector3d& w, const Local& l,
                            Eigen::Matrix<double, 6, 6>& Huw) const {
    if (!project_angle_hessian(u, w, stiffness, l.delta, Huw)) Huw = project_psd<6>(Huw);
  }

  // H = T Huw T^T, T = [u_coeff (x) I, w_coeff (x) I]: columns of vertex j first, then rows.
  void to_vertices(const Eigen::Matrix<double, 6, 6>& Huw, Mat& H) const {
    const auto uu = Huw.topLeftCorner<3, 3>(), uw = Huw.topRightCorner<3, 3>();
    const auto wu = Huw.bottomLeftCorner<3, 3>(), ww = Huw.bottomRightCorner<3, 3>();
    // Vertex block (i, j), i <= j, and its transpose.
    auto set = [&H](int i, int j, const Eigen::Matrix3d& B) {
      H.block<3, 3>(3 * i, 3 * j) = B;
      if (i != j) H.block<3, 3>(3 * j, 3 * i) = B.transpose();
    };
    if (layout == Layout::Corner) {  // u = x1 - x0, w = x2 - x0
      set(0, 0, (uu + uw) + (wu + ww));
      set(0, 1, -uu - wu);
      set(1, 1, uu);
      set(0, 2, -uw - ww);
      set(1, 2, uw);
      set(2, 2, ww);
      return;
    }
    if (layout == Layout::Hinge) {  // u = x1 - x0, w = x2 - x1
      set(0, 0, uu);
      set(0, 1, -(uu - uw));
      set(1, 1, (uu - uw) - (wu - ww));
      set(0, 2, -uw);
      set(1, 2, uw - ww);
      set(2, 2, ww);
      return;
    }
    Eigen::Matrix<double, 6, 3> R[3];
    for (int j = 0; j < 3; ++j) R[j] = u_coeff[j] * Huw.leftCols<3>() + w_coeff[j] * Huw.rightCols<3>();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i <= j; ++i) set(i, j, u_coeff[i] * R[j].topRows<3>() + w_coeff[i] * R[j].bottomRows<3>());
  }

  static Eigen::Vector3d edge(const Vec& x, const Eigen::Vector3d& coeff) {
    return coeff[0] * x.segment<3>(0) + coeff[1] * x.segment<3>(3) + coeff[2] * x.segment<3>(6);
  }

  static double angle(const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
    return std::atan2(u.cross(w).norm(), u.dot(w));
  }

  Local local(const Eigen::Vector3d& u, const Eigen::Vector3d& w) const {
    Local l;
    l.inv_u = 1.0 / u.norm();
    l.inv_w = 1.0 / w.norm();
    l.uh = l.inv_u * u;
    l.wh = l.inv_w * w;
    const double sin = l.uh.cross(l.wh).norm();
    const double cos = l.uh.dot(l.wh);
    const double theta = std::atan2(sin, cos);
    l.cos = cos;
    l.delta = theta - rest_angle;
    l.dc_du = (l.wh - cos * l.uh) * l.inv_u;
    l.dc_dw = (l.uh - cos * l.wh) * l.inv_w;
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
