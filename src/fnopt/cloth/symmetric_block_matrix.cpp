#include <fnopt/cloth/symmetric_block_matrix.hpp>

#include <omp.h>

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
  band_threads_ = 0;
}

namespace {

// y += B z for the 3x3 block B (column-major): the gather of the product.
inline void add_block_product(const double* B, const double* z, double* y) {
  y[0] += B[0] * z[0] + B[3] * z[1] + B[6] * z[2];
  y[1] += B[1] * z[0] + B[4] * z[1] + B[7] * z[2];
  y[2] += B[2] * z[0] + B[5] * z[1] + B[8] * z[2];
}

// y_j += B^T x_i for the block B at row i, column j: the scatter, one expression for the serial and
// the parallel paths so that both round alike.
inline void add_transpose_product(const double* B, double x0, double x1, double x2, double* y) {
  y[0] += B[0] * x0 + B[1] * x1 + B[2] * x2;
  y[1] += B[3] * x0 + B[4] * x1 + B[5] * x2;
  y[2] += B[6] * x0 + B[7] * x1 + B[8] * x2;
}

}  // namespace

void SymmetricBlockMatrix::multiply_rows(const VecX& x, VecX& y, int begin, int end, int scatter_from) const {
  for (int i = begin; i < end; ++i) {
    const double x0 = x[3 * i], x1 = x[3 * i + 1], x2 = x[3 * i + 2];
    double sum[3] = {0.0, 0.0, 0.0};  // the row's blocks left of the diagonal times x
    const int diagonal = row_start_[i + 1] - 1;
    int k = row_start_[i];
    // Columns left of the band (a prefix: a row's columns increase): gathered, not scattered.
    for (; k < diagonal && column_[k] < scatter_from; ++k)
      add_block_product(&values_[9 * static_cast<std::size_t>(k)], &x[3 * column_[k]], sum);
    for (; k < diagonal; ++k) {
      const double* B = &values_[9 * static_cast<std::size_t>(k)];
      add_block_product(B, &x[3 * column_[k]], sum);
      add_transpose_product(B, x0, x1, x2, &y[3 * column_[k]]);
    }
    const double* D = &values_[9 * static_cast<std::size_t>(diagonal)];
    y[3 * i] += sum[0] + D[0] * x0 + D[3] * x1 + D[6] * x2;
    y[3 * i + 1] += sum[1] + D[1] * x0 + D[4] * x1 + D[7] * x2;
    y[3 * i + 2] += sum[2] + D[2] * x0 + D[5] * x1 + D[8] * x2;
  }
}

void SymmetricBlockMatrix::make_bands(int threads) const {
  const int n = block_rows();
  const long blocks = static_cast<long>(column_.size());
  band_row_.assign(1, 0);
  for (int b = 1; b < threads; ++b) {
    int row = band_row_.back();
    while (row < n && row_start_[row] < blocks * b / threads) ++row;
    band_row_.push_back(row);
  }
  band_row_.push_back(n);
  cross_start_.assign(1, 0);
  cross_.clear();
  for (int b = 0; b < threads; ++b) {
    for (int i = band_row_[b + 1]; i < n; ++i)
      for (int k = row_start_[i]; k < row_start_[i + 1] - 1 && column_[k] < band_row_[b + 1]; ++k)
        if (column_[k] >= band_row_[b]) cross_.emplace_back(i, k);
    cross_start_.push_back(static_cast<int>(cross_.size()));
  }
  band_threads_ = threads;
}

void SymmetricBlockMatrix::multiply(const VecX& x, VecX& y) const {
  y.setZero(rows());
  const int n = block_rows();
  const int threads = omp_get_max_threads();
  if (threads == 1 || n < kParallelRows) {
    multiply_rows(x, y, 0, n, 0);
    return;
  }
  if (band_threads_ != threads) make_bands(threads);
#pragma omp parallel num_threads(threads)
  {
    // Bands by thread number, strided in case the team is smaller than asked for.
    for (int b = omp_get_thread_num(); b < threads; b += omp_get_num_threads())
      multiply_rows(x, y, band_row_[b], band_row_[b + 1], band_row_[b]);
#pragma omp barrier
    for (int b = omp_get_thread_num(); b < threads; b += omp_get_num_threads())
      for (int e = cross_start_[b]; e < cross_start_[b + 1]; ++e) {
        const auto [i, k] = cross_[e];
        add_transpose_product(&values_[9 * static_cast<std::size_t>(k)], x[3 * i], x[3 * i + 1], x[3 * i + 2],
                              &y[3 * column_[k]]);
      }
  }
}

}  // namespace fnopt
