#include <fnopt/optimizer/single_precision_factor.hpp>

#include <algorithm>
#include <cstring>

#include <fnopt/util/error.hpp>
#include <fnopt/util/serial_openmp_scope.hpp>

// The reference BLAS interface, as CHOLMOD itself calls it (the library is the one CHOLMOD uses).
extern "C" {
void sgemv_(const char* trans, const int* m, const int* n, const float* alpha, const float* a, const int* lda,
            const float* x, const int* incx, const float* beta, float* y, const int* incy);
void strsv_(const char* uplo, const char* trans, const char* diag, const int* n, const float* a, const int* lda,
            float* x, const int* incx);
}

namespace fnopt {
namespace {

// bfloat16: a float's upper 16 bits, rounded to nearest even (the factor's values are finite).
std::uint16_t to_bfloat16(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  bits += 0x7FFFu + ((bits >> 16) & 1u);
  return static_cast<std::uint16_t>(bits >> 16);
}

inline float from_bfloat16(std::uint16_t value) {
  const std::uint32_t bits = static_cast<std::uint32_t>(value) << 16;
  float result;
  std::memcpy(&result, &bits, sizeof result);
  return result;
}

}  // namespace

void SinglePrecisionFactor::assign(const SparseCholesky& cholesky, Storage storage) {
  const cholmod_factor* L = cholesky.cholmod_factor_pointer();
  require(L != nullptr && L->is_super && L->is_ll && L->itype == CHOLMOD_INT && L->xtype == CHOLMOD_REAL,
          "single-precision factor", "needs a supernodal LL^T factor");
  storage_ = storage;
  rows_ = static_cast<int>(L->n);
  const int supernodes = static_cast<int>(L->nsuper);
  const int* super = static_cast<const int*>(L->super);
  const int* pi = static_cast<const int*>(L->pi);
  const int* px = static_cast<const int*>(L->px);
  first_column_.assign(super, super + supernodes + 1);
  row_start_.assign(pi, pi + supernodes + 1);
  rows_of_.assign(static_cast<const int*>(L->s), static_cast<const int*>(L->s) + pi[supernodes]);
  value_start_.assign(px, px + supernodes + 1);
  const double* x = static_cast<const double*>(L->x);
  permutation_.assign(static_cast<const int*>(L->Perm), static_cast<const int*>(L->Perm) + rows_);
  work_.resize(rows_);
  std::size_t tallest = 0;
  for (int s = 0; s < supernodes; ++s) tallest = std::max<std::size_t>(tallest, pi[s + 1] - pi[s]);
  below_.resize(tallest);
  if (storage == Storage::Float) {
    values_.assign(x, x + px[supernodes]);
    compact_values_.clear();
    pivots_.clear();
    return;
  }
  values_.clear();
  compact_values_.resize(px[supernodes]);
  for (long k = 0; k < px[supernodes]; ++k) compact_values_[k] = to_bfloat16(static_cast<float>(x[k]));
  pivots_.resize(rows_);
  for (int s = 0; s < supernodes; ++s) {
    const int height = pi[s + 1] - pi[s];
    for (int j = super[s]; j < super[s + 1]; ++j)
      pivots_[j] = static_cast<float>(x[px[s] + static_cast<long>(j - super[s]) * (height + 1)]);
  }
}

void SinglePrecisionFactor::solve_in_place(VecX& r) {
  for (int i = 0; i < rows_; ++i) work_[i] = static_cast<float>(r[permutation_[i]]);
  if (storage_ == Storage::Float)
    solve_float();
  else
    solve_bfloat16();
  for (int i = 0; i < rows_; ++i) r[permutation_[i]] = work_[i];
}

void SinglePrecisionFactor::solve_float() {
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  const int one = 1;
  const float plus = 1.0f, minus = -1.0f, zero = 0.0f;
  SerialOpenMpScope serial;  // OpenBLAS's dense blocks on this thread, as CHOLMOD's (sparse_cholesky.cpp)
  // Forward, L y = P r: per supernode, its diagonal block, then the rows below it.
  for (int s = 0; s < supernodes; ++s) {
    const int column = first_column_[s], columns = first_column_[s + 1] - column;
    const int height = row_start_[s + 1] - row_start_[s], below = height - columns;
    const float* block = &values_[value_start_[s]];
    strsv_("L", "N", "N", &columns, block, &height, &work_[column], &one);
    if (below == 0) continue;
    sgemv_("N", &below, &columns, &plus, block + columns, &height, &work_[column], &one, &zero, below_.data(), &one);
    const int* rows = &rows_of_[row_start_[s] + columns];
    for (int i = 0; i < below; ++i) work_[rows[i]] -= below_[i];
  }
  // Back, L^T z = y, in reverse.
  for (int s = supernodes - 1; s >= 0; --s) {
    const int column = first_column_[s], columns = first_column_[s + 1] - column;
    const int height = row_start_[s + 1] - row_start_[s], below = height - columns;
    const float* block = &values_[value_start_[s]];
    if (below > 0) {
      const int* rows = &rows_of_[row_start_[s] + columns];
      for (int i = 0; i < below; ++i) below_[i] = work_[rows[i]];
      sgemv_("T", &below, &columns, &minus, block + columns, &height, below_.data(), &one, &plus, &work_[column], &one);
    }
    strsv_("L", "T", "N", &columns, block, &height, &work_[column], &one);
  }
}

void SinglePrecisionFactor::solve_bfloat16() {
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  float* z = below_.data();  // the supernode's rows: its own columns, then the rows below them
  // Forward, column by column: z_j /= L_jj, then z_i -= L_ij z_j for every row i below j.
  for (int s = 0; s < supernodes; ++s) {
    const int column = first_column_[s], columns = first_column_[s + 1] - column;
    const int height = row_start_[s + 1] - row_start_[s];
    const std::uint16_t* block = &compact_values_[value_start_[s]];
    const int* rows = &rows_of_[row_start_[s] + columns];
    std::copy_n(&work_[column], columns, z);
    std::fill(z + columns, z + height, 0.0f);
    for (int j = 0; j < columns; ++j) {
      const std::uint16_t* l = block + static_cast<long>(j) * height;
      const float zj = z[j] /= pivots_[column + j];
#pragma omp simd
      for (int i = j + 1; i < height; ++i) z[i] -= from_bfloat16(l[i]) * zj;
    }
    std::copy_n(z, columns, &work_[column]);
    for (int i = columns; i < height; ++i) work_[rows[i - columns]] += z[i];
  }
  // Back, in reverse: z_j = (z_j - sum_{i > j} L_ij z_i) / L_jj.
  for (int s = supernodes - 1; s >= 0; --s) {
    const int column = first_column_[s], columns = first_column_[s + 1] - column;
    const int height = row_start_[s + 1] - row_start_[s];
    const std::uint16_t* block = &compact_values_[value_start_[s]];
    const int* rows = &rows_of_[row_start_[s] + columns];
    std::copy_n(&work_[column], columns, z);
    for (int i = columns; i < height; ++i) z[i] = work_[rows[i - columns]];
    for (int j = columns - 1; j >= 0; --j) {
      const std::uint16_t* l = block + static_cast<long>(j) * height;
      float sum = 0.0f;
#pragma omp simd reduction(+ : sum)
      for (int i = j + 1; i < height; ++i) sum += from_bfloat16(l[i]) * z[i];
      z[j] = (z[j] - sum) / pivots_[column + j];
    }
    std::copy_n(z, columns, &work_[column]);
  }
}

}  // namespace fnopt
