#pragma once
// Central differences for the derivative tests: (f(x + eps e_i) - f(x - eps e_i)) / (2 eps),
// accurate to O(eps^2), for a scalar function (its gradient) or a vector function (its
// Jacobian, one column per coordinate). Works on dynamic and fixed-size Eigen vectors.
#include <Eigen/Core>

namespace fnopt::testing {

// f: double(const Vector&). Returns the gradient at x.
template <class Vector, class Function>
Vector central_gradient(Function&& f, const Vector& x, double eps) {
  Vector gradient(x.size());
  Vector shifted = x;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    shifted[i] = x[i] + eps;
    const double plus = f(shifted);
    shifted[i] = x[i] - eps;
    const double minus = f(shifted);
    shifted[i] = x[i];
    gradient[i] = (plus - minus) / (2 * eps);
  }
  return gradient;
}

// g: Vector(const Vector&), the values of the function. Returns the Jacobian at x (rows: g's
// entries, columns: x's coordinates); for a gradient g it is the Hessian.
template <class Vector, class Function>
Eigen::MatrixXd central_jacobian(Function&& g, const Vector& x, double eps) {
  Eigen::MatrixXd jacobian;
  Vector shifted = x;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    shifted[i] = x[i] + eps;
    const Eigen::VectorXd plus = g(shifted);
    shifted[i] = x[i] - eps;
    const Eigen::VectorXd minus = g(shifted);
    shifted[i] = x[i];
    if (i == 0) jacobian.resize(plus.size(), x.size());
    jacobian.col(i) = (plus - minus) / (2 * eps);
  }
  return jacobian;
}

}  // namespace fnopt::testing
