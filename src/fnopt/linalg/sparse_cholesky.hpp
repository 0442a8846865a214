#pragma once
// A sparse Cholesky factor (CHOLMOD, on OpenBLAS) whose solves allocate nothing: Eigen's
// wrapper returns a new dense matrix from every cholmod_solve; here the solution and CHOLMOD's
// workspaces are kept between solves (cholmod_solve2), for solvers that apply one factor at
// every iteration.
//
// Which factorization: supernodal factorizes a cloth Hessian (3 dofs per vertex) 2-4x faster
// (100^2: 364 against 1511 ms) and solves as fast; simplicial solves a scalar grid matrix
// (one row per vertex, 3 right-hand sides) 2x faster (100^2: 2.2 against 4.3 ms). So a factor
// used once per solve is supernodal, a factor kept for a whole rollout is simplicial.
// CHOLMOD analyses both; the supernodal numeric phase is supernodal_factorization.hpp's.
#include <Eigen/CholmodSupport>

#include <fnopt/linalg/supernodal_factorization.hpp>

namespace fnopt {

class SparseCholesky : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  enum class Method { Supernodal, Simplicial };
  explicit SparseCholesky(Method method = Method::Supernodal);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Factorizes A (its lower triangle); false if A is not positive definite. The symbolic
  // analysis is redone unless `pattern` names the pattern analysed last (an id that changes
  // with the sparsity pattern, as BackwardEulerObjective::hessian_pattern_id(); -1: always).
  // CHOLMOD and its BLAS run on the calling thread (util/serial_openmp_scope.hpp).
  bool factorize_matrix(const Eigen::SparseMatrix<double>& A, long pattern = -1);
  // B <- A^-1 B for the rows x cols column-major block at `data` (rows = A's size).
  void solve_in_place(double* data, int rows, int cols);
  // CHOLMOD's factor (null before the first factorization), for copies such as
  // single_precision_factor.hpp's.
  const cholmod_factor* cholmod_factor_pointer() const { return m_cholmodFactor; }

 private:
  long analysed_pattern_ = -1;
  SupernodalFactorization supernodal_;
  cholmod_dense* solution_ = nullptr;
  cholmod_dense* workspace_y_ = nullptr;
  cholmod_dense* workspace_e_ = nullptr;
};

}  // namespace fnopt
