#pragma once
// IPC's smoothed, lagged friction of one vertex against one obstacle (Li et al. 2020, "Incremental
// Potential Contact", §5; docs/design.md §14). At the step's start x_t the normal force magnitude
// lambda = -b'(g(x_t)) and the tangent basis T (3x2, orthonormal, normal to grad d(x_t)) are
// frozen; during the step the tangential displacement relative to the obstacle is
//   u = T^T ((x - x_t) - Delta o),   Delta o the obstacle's translation over the step,
// and the friction potential is D(x) = mu lambda f0(|u|) with IPC's C1 mollifier on eps = eps_v dt:
//   f0(y) = -y^3/(3 eps^2) + y^2/eps + eps/3   (y < eps),   y   (y >= eps),
//   f1(y) = f0'(y) = 2y/eps - y^2/eps^2         (y < eps),   1   (y >= eps).
// grad_x D = mu lambda T (f1(y)/y) u, and in u
//   hess_u f0 = (f1/y) I + (f1' y - f1)/y^3 u u^T
//             = (2/eps - y/eps^2) I - u u^T/(eps^2 y)   (y < eps; (2/eps) I at u = 0),
//             = (I - u u^T/y^2)/y                        (y >= eps),
// both positive semi-definite (eigenvalues 2/eps - 2y/eps^2 >= 0 and 2/eps - y/eps^2 below eps, 0 and
// 1/y above), so hess_x D = mu lambda T hess_u T^T needs no projection.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct FrictionPair {
  int vertex = 0;
  int obstacle = 0;
  double weight = 0.0;                  // mu lambda [N]
  Eigen::Matrix<double, 3, 2> basis;    // T
  Vec3 start = Vec3::Zero();            // x_t of the vertex
  Vec3 obstacle_motion = Vec3::Zero();  // Delta o

  Eigen::Vector2d tangent_displacement(const Vec3& x) const {
    return basis.transpose() * ((x - start) - obstacle_motion);
  }
};

struct FrictionMollifier {
  double epsilon = 0.0;  // eps_v dt [m]

  double f0(double y) const {
    if (y >= epsilon) return y;
    return -y * y * y / (3.0 * epsilon * epsilon) + y * y / epsilon + epsilon / 3.0;
  }
  // f1(y)/y, finite at y = 0.
  double f1_over_y(double y) const { return y >= epsilon ? 1.0 / y : 2.0 / epsilon - y / (epsilon * epsilon); }
  // (f1/y)'(y) / y, the weight of u u^T in hess_u f0 (0 at y = 0, where u u^T vanishes faster).
  double f1_over_y_slope_over_y(double y) const {
    if (y >= epsilon) return -1.0 / (y * y * y);
    return y > 0.0 ? -1.0 / (epsilon * epsilon * y) : 0.0;
  }

  // The potential W f0(|u|) of a tangential displacement u (in the basis T) with weight W = mu lambda;
  // where asked, its gradient in the 3-space of the displacement, W (f1/y) T u, and W T hess_u T^T.
  double tangent_potential(double weight, const Eigen::Matrix<double, 3, 2>& basis, const Eigen::Vector2d& u,
                           Vec3* gradient, Mat3* hessian) const {
    const double y = u.norm();
    if (gradient) *gradient = weight * f1_over_y(y) * (basis * u);
    if (hessian) {
      const Eigen::Matrix2d Hu =
          f1_over_y(y) * Eigen::Matrix2d::Identity() + f1_over_y_slope_over_y(y) * u * u.transpose();
      *hessian = weight * basis * Hu * basis.transpose();
    }
    return weight * f0(y);
  }

  double energy(const FrictionPair& pair, const Vec3& x) const {
    return tangent_potential(pair.weight, pair.basis, pair.tangent_displacement(x), nullptr, nullptr);
  }
  double gradient(const FrictionPair& pair, const Vec3& x, Vec3& g) const {
    return tangent_potential(pair.weight, pair.basis, pair.tangent_displacement(x), &g, nullptr);
  }
  void hessian(const FrictionPair& pair, const Vec3& x, Mat3& H) const {
    tangent_potential(pair.weight, pair.basis, pair.tangent_displacement(x), nullptr, &H);
  }
};

// An orthonormal basis (3x2) of the plane normal to the unit vector n.
inline Eigen::Matrix<double, 3, 2> tangent_basis(const Vec3& n) {
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 t1 = n.cross(helper).normalized();
  Eigen::Matrix<double, 3, 2> T;
  T << t1, n.cross(t1);
  return T;
}

}  // namespace fnopt
