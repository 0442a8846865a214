#include <fnopt/optimizer/symmetric_block_matrix.hpp>

#include <fnopt/optimizer/block_pattern.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

void SymmetricBlockMatrix::read_pattern(const Eigen::SparseMatrix<double>& A) {
  require(A.rows() == A.cols() && A.rows() % 3 == 0 && A.isCompressed(), "symmetric block matrix",
          "the matrix is not square in 3x3 blocks");
  const BlockPattern pattern = read_block_pattern(A, "symmetric block matrix");
  const int n = static_cast<int>(A.rows() / 3);
  row_start_.assign(1, 0);
  column_.clear();
  source_.clear();
  auto add_block = [&](int i, int m) {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) source_.push_back(block_entry(A, i, m, r, c));  // column by column
  };
  for (int i = 0; i < n; ++i) {
    int diagonal = -1;
    for (int k = pattern.row_start[i]; k < pattern.row_start[i + 1]; ++k) {
      const int j = pattern.column[k], m = k - pattern.row_start[i];
      if (j < i) {
        column_.push_back(j);
        add_block(i, m);
      } else if (j == i) {
        diagonal = m;
      }
    }
    require(diagonal >= 0, "symmetric block matrix", "a row has no diagonal block");
    column_.push_back(i);
    add_block(i, diagonal);
    row_start_.push_back(static_cast<int>(source_.size() / 9));
  }
  values_.resize(source_.size());
}

void SymmetricBlockMatrix::assign(const Eigen::SparseMatrix<double>& A, long pattern) {
  if (row_start_.empty() || pattern < 0 || pattern != pattern_) {
    pattern_ = -1;
    read_pattern(A);
    pattern_ = pattern;
  }
  const double* a = A.valuePtr();
  for (std::size_t e = 0; e < source_.size(); ++e) values_[e] = a[source_[e]];
}

void SymmetricBlockMatrix::multiply(const VecX& x, VecX& y) const {
  y.setZero(rows());
  const int n = static_cast<int>(row_start_.size()) - 1;
  for (int i = 0; i < n; ++i) {
    const double x0 = x[3 * i], x1 = x[3 * i + 1], x2 = x[3 * i + 2];
    double y0 = 0.0, y1 = 0.0, y2 = 0.0;
    const int end = row_start_[i + 1] - 1;  // the diagonal block
    for (int k = row_start_[i]; k < end; ++k) {
      const double* B = &values_[9 * static_cast<std::size_t>(k)];
      const int j = column_[k];
      const double z0 = x[3 * j], z1 = x[3 * j + 1], z2 = x[3 * j + 2];
      y0 += B[0] * z0 + B[3] * z1 + B[6] * z2;
      y1 += B[1] * z0 + B[4] * z1 + B[7] * z2;
      y2 += B[2] * z0 + B[5] * z1 + B[8] * z2;
      y[3 * j] += B[0] * x0 + B[1] * x1 + B[2] * x2;
      y[3 * j + 1] += B[3] * x0 + B[4] * x1 + B[5] * x2;
      y[3 * j + 2] += B[6] * x0 + B[7] * x1 + B[8] * x2;
    }
    const double* D = &values_[9 * static_cast<std::size_t>(end)];
    y[3 * i] += y0 + D[0] * x0 + D[3] * x1 + D[6] * x2;
    y[3 * i + 1] += y1 + D[1] * x0 + D[4] * x1 + D[7] * x2;
    y[3 * i + 2] += y2 + D[2] * x0 + D[5] * x1 + D[8] * x2;
  }
}

}  // namespace fnopt
