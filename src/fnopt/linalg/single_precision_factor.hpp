#pragma once
// A single-precision copy of a supernodal Cholesky factor, to precondition with. A solve with the
// factor of a 100^2 cloth Hessian (5.5 million entries) reads the whole factor twice, forward and
// back, and that memory traffic is its cost; in floats it reads half the bytes (docs/design.md
// §6). The solution differs from the double solve by float round-off (2^-24 relative), far below
// what a preconditioner must resolve (the Newton reference's CG stops at relative residuals of
// 1e-2 to 1e-6).
// A factor too large for the caches may keep its values in bfloat16 (float's upper 16 bits, 8
// significant bits; the pivots stay floats, the arithmetic is float): half the bytes again, for a
// coarser preconditioner that costs CG a few more products (docs/design.md §6). Both storages run
// one written-out solve, four columns of a supernode at a time (solve(), below).
#include <cstdint>
#include <vector>

#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class SinglePrecisionFactor {
 public:
  enum class Storage { Float, BFloat16 };

  // Copies the supernodal LL^T factor of `cholesky` and its fill-reducing permutation, its values
  // rounded to `storage`; throws Error if it holds no factor or a simplicial one.
  void assign(const SparseCholesky& cholesky, Storage storage = Storage::Float);
  int rows() const { return rows_; }
  Storage storage() const { return storage_; }
  // r <- A^-1 r = P^T L^-T L^-1 P r, the triangular solves in floats; no allocation.
  void solve_in_place(VecX& r);

 private:
  // The forward and back solves on the values in either storage (float, or uint16_t holding
  // bfloat16, each value widened to a float as it is read), the arithmetic in floats.
  template <class Value>
  void solve(const Value* values);
  template <class Value>
  void forward_solve(const Value* values);
  // Supernode s: its first column and column count, its rows (the columns' own, then those below:
  // `rows` holds the latter's indices), its values column by column and its columns' pivots.
  template <class Value>
  struct Supernode {
    int column, columns, height;
    const Value* block;
    const float* pivot;
    const int* rows;
  };
  template <class Value>
  Supernode<Value> supernode(int s, const Value* values) const;
  template <class Value>
  void back_solve(const Value* values);

  Storage storage_ = Storage::Float;
  int rows_ = 0;
  std::vector<int> first_column_;  // supernode s holds columns [first_column_[s], first_column_[s + 1])
  std::vector<int> row_start_;     // its row indices: rows_of_[row_start_[s] .. row_start_[s + 1])
  std::vector<int> rows_of_;
  std::vector<long> value_start_;  // its dense column-major block (rows x columns) at values_[value_start_[s]]
  std::vector<float> values_;      // Float
  std::vector<std::uint16_t> compact_values_;  // BFloat16: the same layout
  std::vector<float> pivots_;                  // L's diagonal, by column
  std::vector<int> permutation_;               // (P r)_i = r[permutation_[i]]
  std::vector<float> work_;
  std::vector<float> supernode_rows_;  // one supernode's rows of the solution: its own columns, then those below
};

}  // namespace fnopt
