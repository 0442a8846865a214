#pragma once
// A single-precision copy of a supernodal Cholesky factor, to precondition with. A solve with the
// factor of a 100^2 cloth Hessian (5.5 million entries) reads the whole factor twice, forward and
// back, and that memory traffic is its cost; in floats it reads half the bytes and takes half
// the time (docs/results.md, "The Newton reference"). The solution differs from the double
// solve by about 1e-7 of its norm, far below what a preconditioner must resolve (the Newton
// reference's CG stops at relative residuals of 1e-2 to 1e-6).
// A factor too large for the caches may keep its values in bfloat16 (float's upper 16 bits, 8
// significant bits; the pivots stay floats, the arithmetic is float): half the bytes again, a
// 100^2 solve 1.9x faster, and a solution about 3e-3 of its norm from the double one, which costs
// CG about 1.5 % more products (docs/results.md, "The factor's solves are bound by this core's
// memory bandwidth"). Both storages run one written-out solve, four columns of a supernode at a
// time ("The factor's solves in panels of four columns").
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
