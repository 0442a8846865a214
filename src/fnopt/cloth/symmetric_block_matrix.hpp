#pragma once
// A symmetric matrix of 3x3 blocks kept as its lower triangle, diagonal blocks included, in
// doubles: y = A x reads each kept block once, gathering A_ij x_j into y_i and scattering
// A_ij^T x_i into y_j. HessianAssembly fills it in place of the whole CSC matrix where only
// products are needed (the Newton reference's CG): half the values to write, and a product reads
// a third of the bytes of Eigen's with the whole CSC matrix, whose every entry carries its row
// index (docs/design.md §6). With several OpenMP threads and enough rows
// the rows are cut into one band per thread asked for (a smaller team takes them in turn); a band's
// rows scatter only into the band, and the scatters into earlier bands are added after a barrier,
// per column in increasing row order: every y_j is the same sum in the same order as on one thread,
// so the product is the same bit for bit on any number of threads. The bands are made on the first
// product with a new thread count and kept (like StencilTerm's buffers): a matrix is not safe to
// multiply from two threads at once.
#include <algorithm>
#include <utility>
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
  // y = A x; no allocation once y has the size (and the bands for this thread count are made).
  void multiply(const VecX& x, VecX& y) const;
  Eigen::Index rows() const { return 3 * static_cast<Eigen::Index>(block_rows()); }

  // Block rows from which the product runs on several threads (below, the parallel region costs
  // more than it saves).
  static constexpr int kParallelRows = 2048;

 private:
  int block_rows() const { return row_start_.empty() ? 0 : static_cast<int>(row_start_.size()) - 1; }
  // Rows [begin, end) of the product: each row's gather, and the scatters into columns from
  // `scatter_from` on (the band's own; earlier bands' are added after multiply's barrier).
  void multiply_rows(const VecX& x, VecX& y, int begin, int end, int scatter_from) const;
  // The bands for `threads` threads, balanced by blocks, and each band's blocks in later rows.
  void make_bands(int threads) const;

  std::vector<int> row_start_, column_;
  std::vector<double> values_;
  // The parallel product's bands (made on the first product with a new thread count or pattern):
  // band b holds rows [band_row_[b], band_row_[b + 1]); cross_[cross_start_[b] ..] are the blocks
  // (row, block index) of later bands' rows in band b's columns, by row: each column's in the order
  // the serial product adds them.
  mutable int band_threads_ = 0;
  mutable std::vector<int> band_row_, cross_start_;
  mutable std::vector<std::pair<int, int>> cross_;
};

}  // namespace fnopt
