#pragma once
// Edge stretch (docs/design.md §2): per grid edge e = x1 - x0,
//   E = (k/2) h^2 (|e|/h - 1)^2 = (k/2) (|e| - h)^2.
// Gradient w.r.t. e: k (|e| - h) e/|e|. Hessian w.r.t. e:
//   k [ (1 - h/|e|) (I - e e^T/|e|^2) + e e^T/|e|^2 ],
// whose only possibly negative eigenvalue is the transverse k (1 - h/|e|) of a compressed edge:
// the projection (psd_projection.hpp) replaces it with its absolute value, in closed form.
#include <Eigen/Core>
#include <cmath>
#include <utility>

namespace fnopt {

struct StretchKernel {
  static constexpr int kVertices = 2;
  using Vec = Eigen::Matrix<double, 6, 1>;
  using Mat = Eigen::Matrix<double, 6, 6>;

  double stiffness = 0.0;    // k [N/m]
  double rest_length = 0.0;  // h [m]

  double energy(const Vec& x) const {
    const double stretch = (x.tail<3>() - x.head<3>()).norm() - rest_length;
    return 0.5 * stiffness * stretch * stretch;
  }

  double gradient(const Vec& x, Vec& g) const {
    const Eigen::Vector3d e = x.tail<3>() - x.head<3>();
    const double length = e.norm();
    const double stretch = length - rest_length;
    const Eigen::Vector3d ge = stiffness * stretch / length * e;
    g << -ge, ge;
    return 0.5 * stiffness * stretch * stretch;
  }

  void hessian(const Vec& x, Mat& H, bool project) const {
    const auto [axial, transverse] = axial_and_transverse(x);
    fill(axial, project ? std::abs(transverse) : transverse, H);
  }

  // hessian(x, exact, false) and hessian(x, projected, true) from one evaluation.
  void hessian_pair(const Vec& x, Mat& exact, Mat& projected) const {
    const auto [axial, transverse] = axial_and_transverse(x);
    fill(axial, transverse, exact);
    if (transverse < 0.0)
      fill(axial, -transverse, projected);
    else
      projected = exact;
  }

 private:
  // e e^T / |e|^2 and the transverse factor 1 - h/|e| of the Hessian above.
  std::pair<Eigen::Matrix3d, double> axial_and_transverse(const Vec& x) const {
    const Eigen::Vector3d e = x.tail<3>() - x.head<3>();
    const double length = e.norm();
    return {e * e.transpose() / (length * length), 1.0 - rest_length / length};
  }

  void fill(const Eigen::Matrix3d& axial, double transverse, Mat& H) const {
    const Eigen::Matrix3d He = stiffness * (transverse * (Eigen::Matrix3d::Identity() - axial) + axial);
    H << He, -He, -He, He;
  }
};

}  // namespace fnopt
