#include <fnopt/optimizer/single_precision_factor.hpp>

#include <algorithm>

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

void SinglePrecisionFactor::assign(const SparseCholesky& cholesky) {
  const cholmod_factor* L = cholesky.cholmod_factor_pointer();
  require(L != nullptr && L->is_super && L->is_ll && L->itype == CHOLMOD_INT && L->xtype == CHOLMOD_REAL,
          "single-precision factor", "needs a supernodal LL^T factor");
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
  values_.assign(x, x + px[supernodes]);
  permutation_.assign(static_cast<const int*>(L->Perm), static_cast<const int*>(L->Perm) + rows_);
  work_.resize(rows_);
  std::size_t widest = 0;
  for (int s = 0; s < supernodes; ++s)
    widest = std::max<std::size_t>(widest, (pi[s + 1] - pi[s]) - (super[s + 1] - super[s]));
  below_.resize(widest);
}

void SinglePrecisionFactor::solve_in_place(VecX& r) {
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  const int one = 1;
  const float plus = 1.0f, minus = -1.0f, zero = 0.0f;
  SerialOpenMpScope serial;  // OpenBLAS's dense blocks on this thread, as CHOLMOD's (sparse_cholesky.cpp)
  for (int i = 0; i < rows_; ++i) work_[i] = static_cast<float>(r[permutation_[i]]);
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
  for (int i = 0; i < rows_; ++i) r[permutation_[i]] = work_[i];
}

}  // namespace fnopt
