#pragma once
// Plain preconditioned CG on a symmetric positive definite matrix, for tests that measure a
// preconditioner's strength: the number of products with A to ||A x - b|| <= tolerance ||b||.
#include <Eigen/Sparse>

#include <fnopt/util/types.hpp>

namespace fnopt::testing {

// precondition(r): r <- M^-1 r in place. Returns the products taken, or max_iterations + 1 if the
// tolerance was not reached; the iterate goes to *solution when given.
template <class Precondition>
int pcg_iterations(const Eigen::SparseMatrix<double>& A, const VecX& b, Precondition&& precondition, double tolerance,
                   int max_iterations, VecX* solution = nullptr) {
  VecX x = VecX::Zero(b.size()), r = b, z = r;
  precondition(z);
  VecX p = z;
  double rz = r.dot(z);
  int k = 1;
  for (; k <= max_iterations; ++k) {
    const VecX Ap = A * p;
    const double alpha = rz / p.dot(Ap);
    x += alpha * p;
    r -= alpha * Ap;
    if (r.norm() <= tolerance * b.norm()) break;
    z = r;
    precondition(z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  if (solution != nullptr) *solution = x;
  return k;
}

}  // namespace fnopt::testing
