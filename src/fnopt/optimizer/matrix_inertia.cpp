#include <fnopt/optimizer/matrix_inertia.hpp>

#include <Eigen/SparseCholesky>

namespace fnopt {

int negative_eigenvalue_count(const Eigen::SparseMatrix<double>& a) {
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
  if (ldlt.info() != Eigen::Success) return -1;
  const Eigen::VectorXd d = ldlt.vectorD();  // by value: an expression on it would dangle
  if (!d.allFinite() || (d.array() == 0.0).any()) return -1;
  return static_cast<int>((d.array() < 0.0).count());
}

}  // namespace fnopt
