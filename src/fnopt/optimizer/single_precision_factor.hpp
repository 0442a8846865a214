#pragma once
// A single-precision copy of a supernodal Cholesky factor, to precondition with. A solve with the
// factor of a 100^2 cloth Hessian (5.5 million entries) reads the whole factor twice, forward and
// back, and that memory traffic is its cost; in floats it reads half the bytes and takes half
// the time (docs/results.md, "The Newton reference"). The solution differs from the double
// solve by about 1e-7 of its norm, far below what a preconditioner must resolve (the Newton
// reference's CG stops at relative residuals of 1e-2 to 1e-6).
#include <vector>

#include <fnopt/optimizer/sparse_cholesky.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class SinglePrecisionFactor {
 public:
  // Copies the supernodal LL^T factor of `cholesky` and its fill-reducing permutation; throws
  // Error if it holds no factor or a simplicial one.
  void assign(const SparseCholesky& cholesky);
  int rows() const { return rows_; }
  // r <- A^-1 r = P^T L^-T L^-1 P r, the triangular solves in floats; no allocation.
  void solve_in_place(VecX& r);

 private:
  int rows_ = 0;
  std::vector<int> first_column_;  // supernode s holds columns [first_column_[s], first_column_[s + 1])
  std::vector<int> row_start_;     // its row indices: rows_of_[row_start_[s] .. row_start_[s + 1])
  std::vector<int> rows_of_;
  std::vector<long> value_start_;  // its dense column-major block (rows x columns) at values_[value_start_[s]]
  std::vector<float> values_;
  std::vector<int> permutation_;  // (P r)_i = r[permutation_[i]]
  std::vector<float> work_, below_;
};

}  // namespace fnopt
