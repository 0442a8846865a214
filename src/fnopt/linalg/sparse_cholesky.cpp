#include <fnopt/linalg/sparse_cholesky.hpp>

#include <cassert>
#include <cstring>

#include <fnopt/util/serial_openmp_scope.hpp>

namespace fnopt {

SparseCholesky::SparseCholesky(Method method) {
  setMode(method == Method::Supernodal ? Eigen::CholmodSupernodalLLt : Eigen::CholmodSimplicialLLt);
  cholmod().print = 0;  // an indefinite matrix is an expected outcome, reported by the return value
}

SparseCholesky::~SparseCholesky() {
  for (cholmod_dense** dense : {&solution_, &workspace_y_, &workspace_e_})
    if (*dense) cholmod_free_dense(dense, &cholmod());
}

bool SparseCholesky::factorize_matrix(const Eigen::SparseMatrix<double>& A, long pattern) {
  SerialOpenMpScope serial;
  const bool analyse = pattern < 0 || pattern != analysed_pattern_ || rows() != A.rows();
  if (analyse) {
    analyzePattern(A);
    analysed_pattern_ = pattern;
  }
  if (!m_cholmodFactor->is_super) {
    factorize(A);
    return info() == Eigen::Success;
  }
  if (analyse) supernodal_.analyse(A, m_cholmodFactor, &cholmod());
  m_info = supernodal_.factorize(A, m_cholmodFactor) ? Eigen::Success : Eigen::NumericalIssue;
  m_factorizationIsOk = true;
  return m_info == Eigen::Success;
}

void SparseCholesky::solve_in_place(double* data, int rows, int cols) {
  assert(m_cholmodFactor && static_cast<int>(m_cholmodFactor->n) == rows);
  cholmod_dense rhs{};
  rhs.nrow = rows;
  rhs.ncol = cols;
  rhs.nzmax = static_cast<std::size_t>(rows) * cols;
  rhs.d = rows;
  rhs.x = data;
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  SerialOpenMpScope serial;
  // Allocates the solution and workspaces on the first call only (and when the size changes).
  cholmod_solve2(CHOLMOD_A, m_cholmodFactor, &rhs, nullptr, &solution_, nullptr, &workspace_y_, &workspace_e_,
                 &cholmod());
  std::memcpy(data, solution_->x, sizeof(double) * rhs.nzmax);
}

}  // namespace fnopt
