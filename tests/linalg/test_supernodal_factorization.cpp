// The supernodal numeric phase gives CHOLMOD's own factor bit for bit (the same blocks, BLAS calls
// and order of updates), on a cloth Hessian of many supernodes: after a fresh analysis, for new
// values on the analysed pattern, and after an indefinite matrix, which it reports at CHOLMOD's
// column; a matrix of another pattern under the analysed one's id is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/util/serial_openmp_scope.hpp>
#include "tests/util/swinging_cloth_hessian.hpp"

namespace fnopt {
namespace {

// CHOLMOD's own analysis and numeric factorization (Eigen's wrapper), with its factor in view; on
// one thread, as fnopt runs it (a threaded BLAS sums some blocks in another order).
class CholmodFactor : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  explicit CholmodFactor(const Eigen::SparseMatrix<double>& A) {
    cholmod().print = 0;
    SerialOpenMpScope serial;
    compute(A);
  }
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};

// Whether two numeric supernodal factors have the same permutation, supernodes and values, bit for bit.
::testing::AssertionResult same_factor(const cholmod_factor* ours, const cholmod_factor* cholmod) {
  if (!ours->is_super || !cholmod->is_super || ours->xtype != CHOLMOD_REAL || cholmod->xtype != CHOLMOD_REAL)
    return ::testing::AssertionFailure() << "not two numeric supernodal factors";
  if (ours->n != cholmod->n || ours->nsuper != cholmod->nsuper || ours->xsize != cholmod->xsize)
    return ::testing::AssertionFailure() << "different sizes";
  if (std::memcmp(ours->Perm, cholmod->Perm, sizeof(int) * ours->n) != 0)
    return ::testing::AssertionFailure() << "different permutations";
  const double* x = static_cast<const double*>(ours->x);
  const double* y = static_cast<const double*>(cholmod->x);
  for (std::size_t k = 0; k < ours->xsize; ++k)
    if (std::memcmp(&x[k], &y[k], sizeof(double)) != 0)
      return ::testing::AssertionFailure()
             << "value " << k << " of " << ours->xsize << ": " << x[k] << " against " << y[k];
  return ::testing::AssertionSuccess();
}

TEST(SupernodalFactorization, GivesCholmodsFactorBitForBit) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian();
  SparseCholesky ours;
  ASSERT_TRUE(ours.factorize_matrix(A));
  const CholmodFactor cholmod(A);
  ASSERT_EQ(cholmod.info(), Eigen::Success);
  EXPECT_GT(ours.cholmod_factor_pointer()->nsuper, 100u);
  EXPECT_TRUE(same_factor(ours.cholmod_factor_pointer(), cholmod.factor()));
  EXPECT_EQ(ours.cholmod_factor_pointer()->minor, ours.cholmod_factor_pointer()->n);

  const VecX b = VecX::Random(A.rows());
  VecX x = b;
  ours.solve_in_place(x.data(), static_cast<int>(x.size()), 1);
  EXPECT_LT((A.selfadjointView<Eigen::Lower>() * x - b).norm(), 1e-10 * b.norm());
}

TEST(SupernodalFactorization, RefactorsNewValuesOnTheAnalysedPattern) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian();
  Eigen::SparseMatrix<double> B = A;
  for (int j = 0; j < B.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(B, j); it; ++it)
      it.valueRef() *= it.row() == j ? 1.0 + 0.5 * std::sin(j) * std::sin(j) : 0.8;
  SparseCholesky ours;
  ASSERT_TRUE(ours.factorize_matrix(A, 7));
  ASSERT_TRUE(ours.factorize_matrix(B, 7));  // no new analysis
  EXPECT_TRUE(same_factor(ours.cholmod_factor_pointer(), CholmodFactor(B).factor()));
}

TEST(SupernodalFactorization, ReportsAnIndefiniteMatrixAtCholmodsColumnAndRecovers) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian();
  Eigen::SparseMatrix<double> indefinite = A;
  indefinite.coeffRef(A.rows() / 2, A.rows() / 2) = -1.0;
  SparseCholesky ours;
  ASSERT_TRUE(ours.factorize_matrix(A, 7));
  EXPECT_FALSE(ours.factorize_matrix(indefinite, 7));
  EXPECT_EQ(ours.info(), Eigen::NumericalIssue);
  const CholmodFactor cholmod(indefinite);
  EXPECT_EQ(cholmod.info(), Eigen::NumericalIssue);
  EXPECT_EQ(ours.cholmod_factor_pointer()->minor, cholmod.factor()->minor);
  EXPECT_LT(ours.cholmod_factor_pointer()->minor, ours.cholmod_factor_pointer()->n);

  ASSERT_TRUE(ours.factorize_matrix(A, 7));
  EXPECT_EQ(ours.info(), Eigen::Success);
  EXPECT_TRUE(same_factor(ours.cholmod_factor_pointer(), CholmodFactor(A).factor()));
}

TEST(SupernodalFactorization, RefusesAMatrixOfAnotherPattern) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian(12);
  Eigen::SparseMatrix<double> fewer = A;
  fewer.prune([](Eigen::Index i, Eigen::Index j, double) { return i != j + 1; });
  ASSERT_LT(fewer.nonZeros(), A.nonZeros());
  SparseCholesky ours;
  ASSERT_TRUE(ours.factorize_matrix(A, 7));
  // A caller's mistake, not a user's: std::logic_error rather than fnopt::Error.
  EXPECT_THROW(ours.factorize_matrix(fewer, 7), std::logic_error);
  EXPECT_TRUE(ours.factorize_matrix(fewer, 8));  // a new pattern id: analysed again
}

}  // namespace
}  // namespace fnopt
