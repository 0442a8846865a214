#include <fnopt/linalg/single_precision_factor.hpp>

#include <algorithm>
#include <cstring>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// bfloat16: a float's upper 16 bits, rounded to nearest even (the factor's values are finite).
std::uint16_t to_bfloat16(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  bits += 0x7FFFu + ((bits >> 16) & 1u);
  return static_cast<std::uint16_t>(bits >> 16);
}

inline float widen(float value) { return value; }

inline float widen(std::uint16_t value) {
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
  supernode_rows_.resize(tallest);
  // The pivots in floats for both storages: the divisions keep float precision.
  pivots_.resize(rows_);
  for (int s = 0; s < supernodes; ++s) {
    const int height = pi[s + 1] - pi[s];
    for (int j = super[s]; j < super[s + 1]; ++j)
      pivots_[j] = static_cast<float>(x[px[s] + static_cast<long>(j - super[s]) * (height + 1)]);
  }
  if (storage == Storage::Float) {
    values_.assign(x, x + px[supernodes]);
    compact_values_.clear();
  } else {
    values_.clear();
    compact_values_.resize(px[supernodes]);
    for (long k = 0; k < px[supernodes]; ++k) compact_values_[k] = to_bfloat16(static_cast<float>(x[k]));
  }
}

// A supernode's columns go a panel of four at a time: each pass over the rows below the panel reads
// their z once for four columns (column by column, the loads and stores of z cost as much as reading
// the factor: docs/design.md §6). The loops are
// written out in each pass: as inline helpers GCC ran their scalar loops.
template <class Value>
void SinglePrecisionFactor::solve(const Value* values) {
  forward_solve(values);
  back_solve(values);
}

template <class Value>
SinglePrecisionFactor::Supernode<Value> SinglePrecisionFactor::supernode(int s, const Value* values) const {
  const int column = first_column_[s], columns = first_column_[s + 1] - column;
  return {column, columns, row_start_[s + 1] - row_start_[s], values + value_start_[s], &pivots_[column],
          &rows_of_[row_start_[s] + columns]};
}

// Forward: z_j /= L_jj, then z_i -= L_ij z_j for every row i below j; in a panel, the same
// operations in the same order as column by column.
template <class Value>
void SinglePrecisionFactor::forward_solve(const Value* values) {
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  float* z = supernode_rows_.data();
  for (int s = 0; s < supernodes; ++s) {
    const auto [column, columns, height, block, pivot, rows] = supernode(s, values);
    std::copy_n(&work_[column], columns, z);
    std::fill(z + columns, z + height, 0.0f);
    int j = 0;
    for (; j + 4 <= columns; j += 4) {
      const Value* l0 = block + static_cast<long>(j) * height;
      const Value *l1 = l0 + height, *l2 = l1 + height, *l3 = l2 + height;
      const float z0 = z[j] /= pivot[j];
      z[j + 1] -= widen(l0[j + 1]) * z0;
      z[j + 2] -= widen(l0[j + 2]) * z0;
      z[j + 3] -= widen(l0[j + 3]) * z0;
      const float z1 = z[j + 1] /= pivot[j + 1];
      z[j + 2] -= widen(l1[j + 2]) * z1;
      z[j + 3] -= widen(l1[j + 3]) * z1;
      const float z2 = z[j + 2] /= pivot[j + 2];
      z[j + 3] -= widen(l2[j + 3]) * z2;
      const float z3 = z[j + 3] /= pivot[j + 3];
#pragma omp simd
      for (int i = j + 4; i < height; ++i)
        z[i] = (((z[i] - widen(l0[i]) * z0) - widen(l1[i]) * z1) - widen(l2[i]) * z2) - widen(l3[i]) * z3;
    }
    for (; j < columns; ++j) {
      const Value* l = block + static_cast<long>(j) * height;
      const float zj = z[j] /= pivot[j];
#pragma omp simd
      for (int i = j + 1; i < height; ++i) z[i] -= widen(l[i]) * zj;
    }
    std::copy_n(z, columns, &work_[column]);
    for (int i = columns; i < height; ++i) work_[rows[i - columns]] += z[i];
  }
}

// Back, in reverse: z_j = (z_j - sum_{i > j} L_ij z_i) / L_jj; in a panel, its four sums over the
// rows below it in one pass, then its own rows from the last column to the first.
template <class Value>
void SinglePrecisionFactor::back_solve(const Value* values) {
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  float* z = supernode_rows_.data();
  for (int s = supernodes - 1; s >= 0; --s) {
    const auto [column, columns, height, block, pivot, rows] = supernode(s, values);
    std::copy_n(&work_[column], columns, z);
    for (int i = columns; i < height; ++i) z[i] = work_[rows[i - columns]];
    int j = columns - 1;
    for (; j >= 3; j -= 4) {  // columns j-3 .. j
      const Value* l3 = block + static_cast<long>(j) * height;
      const Value *l2 = l3 - height, *l1 = l2 - height, *l0 = l1 - height;
      float s0 = 0.0f, s1 = 0.0f, s2 = 0.0f, s3 = 0.0f;
#pragma omp simd reduction(+ : s0, s1, s2, s3)
      for (int i = j + 1; i < height; ++i) {
        const float zi = z[i];
        s3 += widen(l3[i]) * zi;
        s2 += widen(l2[i]) * zi;
        s1 += widen(l1[i]) * zi;
        s0 += widen(l0[i]) * zi;
      }
      const float z3 = z[j] = (z[j] - s3) / pivot[j];
      s2 += widen(l2[j]) * z3;
      s1 += widen(l1[j]) * z3;
      s0 += widen(l0[j]) * z3;
      const float z2 = z[j - 1] = (z[j - 1] - s2) / pivot[j - 1];
      s1 += widen(l1[j - 1]) * z2;
      s0 += widen(l0[j - 1]) * z2;
      const float z1 = z[j - 2] = (z[j - 2] - s1) / pivot[j - 2];
      s0 += widen(l0[j - 2]) * z1;
      z[j - 3] = (z[j - 3] - s0) / pivot[j - 3];
    }
    for (; j >= 0; --j) {
      const Value* l = block + static_cast<long>(j) * height;
      float sum = 0.0f;
#pragma omp simd reduction(+ : sum)
      for (int i = j + 1; i < height; ++i) sum += widen(l[i]) * z[i];
      z[j] = (z[j] - sum) / pivot[j];
    }
    std::copy_n(z, columns, &work_[column]);
  }
}

void SinglePrecisionFactor::solve_in_place(VecX& r) {
  for (int i = 0; i < rows_; ++i) work_[i] = static_cast<float>(r[permutation_[i]]);
  if (storage_ == Storage::Float)
    solve(values_.data());
  else
    solve(compact_values_.data());
  for (int i = 0; i < rows_; ++i) r[permutation_[i]] = work_[i];
}

}  // namespace fnopt
