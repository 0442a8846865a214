#include <fnopt/cloth/symmetric_block_matrix.hpp>

#include <fnopt/util/error.hpp>

namespace fnopt {

void SymmetricBlockMatrix::set_pattern(std::vector<int> row_start, std::vector<int> column) {
  const int n = static_cast<int>(row_start.size()) - 1;
  require(n >= 0 && row_start.front() == 0 && row_start.back() == static_cast<int>(column.size()),
          "symmetric block matrix", "row starts do not span the columns");
  for (int i = 0; i < n; ++i) {
    const int begin = row_start[i], end = row_start[i + 1];
    require(end > begin && column[end - 1] == i, "symmetric block matrix",
            "a row does not end with its diagonal block");
    for (int k = begin; k + 1 < end; ++k)
      require(column[k] >= 0 && column[k] < i && (k == begin || column[k - 1] < column[k]), "symmetric block matrix",
              "a row's columns are not increasing and left of the diagonal");
  }
  row_start_ = std::move(row_start);
  column_ = std::move(column);
  values_.assign(9 * column_.size(), 0.0);
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
