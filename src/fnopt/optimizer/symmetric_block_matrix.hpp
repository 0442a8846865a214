#pragma once
// A symmetric matrix of 3x3 blocks kept for products as its lower triangle, diagonal blocks
// included, in doubles: y = A x reads each kept block once, gathering A_ij x_j into y_i and
// scattering A_ij^T x_i into y_j. The Newton reference's products with the exact Hessian H are
// bound by memory traffic, and Eigen's product with the whole CSC matrix reads every entry with its
// row index: three times the bytes (docs/results.md, "The reference's kernels").
#include <Eigen/Sparse>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class SymmetricBlockMatrix {
 public:
  // From a symmetric matrix with both triangles stored, in 3x3 blocks (as HessianAssembly builds
  // it). Its pattern is read again only when `pattern` differs from the last one (an id that
  // changes with it, as BackwardEulerObjective::hessian_pattern_id(); -1: always); otherwise only
  // the values are copied. Throws Error if A is not made of 3x3 blocks.
  void assign(const Eigen::SparseMatrix<double>& A, long pattern = -1);
  // y = A x; no allocation once y has the size.
  void multiply(const VecX& x, VecX& y) const;
  Eigen::Index rows() const { return 3 * static_cast<Eigen::Index>(row_start_.empty() ? 0 : row_start_.size() - 1); }

 private:
  void read_pattern(const Eigen::SparseMatrix<double>& A);

  long pattern_ = -1;
  // Row i's kept blocks at [row_start_[i], row_start_[i + 1]), columns j < i in column_, then its
  // diagonal block last; block k's 3x3 values column by column at values_[9k], copied from
  // A.valuePtr()[source_[9k + e]].
  std::vector<int> row_start_, column_, source_;
  std::vector<double> values_;
};

}  // namespace fnopt
