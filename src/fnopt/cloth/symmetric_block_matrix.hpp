#pragma once
// A symmetric matrix of 3x3 blocks kept as its lower triangle, diagonal blocks included, in
// doubles: y = A x reads each kept block once, gathering A_ij x_j into y_i and scattering
// A_ij^T x_i into y_j. HessianAssembly fills it in place of the whole CSC matrix where only
// products are needed (the Newton reference's CG): half the values to write, and a product reads
// a third of the bytes of Eigen's with the whole CSC matrix, whose every entry carries its row
// index (docs/results.md, "The reference's kernels").
#include <algorithm>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class SymmetricBlockMatrix {
 public:
  // Row i's blocks are [row_start[i], row_start[i + 1]): its columns j < i in increasing order
  // (column[k]), then its diagonal block. Values zeroed. Throws Error on a malformed pattern.
  void set_pattern(std::vector<int> row_start, std::vector<int> column);
  // The index of row i's first block.
  int row_begin(int i) const { return row_start_[i]; }
  // Block k's 3x3 values, column by column, at values()[9k].
  double* values() { return values_.data(); }
  const std::vector<double>& value_array() const { return values_; }
  void set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }
  void scale(double factor) {
    for (double& v : values_) v *= factor;
  }
  // y = A x; no allocation once y has the size.
  void multiply(const VecX& x, VecX& y) const;
  Eigen::Index rows() const { return 3 * static_cast<Eigen::Index>(row_start_.empty() ? 0 : row_start_.size() - 1); }

 private:
  std::vector<int> row_start_, column_;
  std::vector<double> values_;
};

}  // namespace fnopt
