#include <fnopt/linalg/matrix_inertia.hpp>

#include <Eigen/SparseCholesky>

namespace fnopt {
namespace {

// The count of negative pivots of a's LDL^T (-1 at a zero pivot), and z if `direction` is given
// and the count is positive.
int factor_inertia(const Eigen::SparseMatrix<double>& a, Eigen::VectorXd* direction) {
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
  if (ldlt.info() != Eigen::Success) return -1;
  const Eigen::VectorXd d = ldlt.vectorD();  // by value: an expression on it would dangle
  if (!d.allFinite() || (d.array() == 0.0).any()) return -1;
  const int negative = static_cast<int>((d.array() < 0.0).count());
  if (direction && negative > 0) {
    Eigen::VectorXd s = (d.array() < 0.0).cast<double>().matrix();
    ldlt.matrixU().solveInPlace(s);  // L^-T s
    *direction = ldlt.permutationPinv() * s;
  }
  return negative;
}

}  // namespace

int negative_eigenvalue_count(const Eigen::SparseMatrix<double>& a) { return factor_inertia(a, nullptr); }

int negative_curvature_direction(const Eigen::SparseMatrix<double>& a, Eigen::VectorXd& z) {
  return factor_inertia(a, &z);
}

}  // namespace fnopt
