// The single-precision copy of a supernodal factor solves the same system as CHOLMOD's double
// solve, to float round-off, on a cloth's projected Hessian large enough for many supernodes; its
// bfloat16 values solve it to a few 1e-3 and still precondition CG to convergence in a few products.
// The solves go four columns of a supernode at a time and the last one to three columns one by one;
// this factor has supernodes of every width modulo four, so every path is checked.
#include <gtest/gtest.h>

#include <set>

#include <fnopt/linalg/single_precision_factor.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/preconditioned_cg.hpp"
#include "tests/util/swinging_cloth_hessian.hpp"

namespace fnopt {
namespace {

// The widths modulo 4 of the supernodes that hold at least one panel of four columns.
std::set<int> panel_remainders(const cholmod_factor* L) {
  const int* super = static_cast<const int*>(L->super);
  std::set<int> remainders;
  for (std::size_t s = 0; s < L->nsuper; ++s)
    if (const int columns = super[s + 1] - super[s]; columns >= 4) remainders.insert(columns % 4);
  return remainders;
}

TEST(SinglePrecisionFactor, SolvesTheSystemOfTheDoubleFactor) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian();
  SparseCholesky cholesky;
  ASSERT_TRUE(cholesky.factorize_matrix(A));
  EXPECT_EQ(panel_remainders(cholesky.cholmod_factor_pointer()), (std::set<int>{0, 1, 2, 3}));
  SinglePrecisionFactor single;
  single.assign(cholesky);
  ASSERT_EQ(single.rows(), A.rows());
  for (int trial = 0; trial < 3; ++trial) {
    const VecX b = VecX::Random(A.rows());
    VecX in_doubles = b, in_floats = b;
    cholesky.solve_in_place(in_doubles.data(), static_cast<int>(b.size()), 1);
    single.solve_in_place(in_floats);
    EXPECT_LT((in_floats - in_doubles).norm(), 1e-5 * in_doubles.norm());
    EXPECT_LT((A * in_floats - b).norm(), 1e-4 * b.norm());
  }
}

// In bfloat16 (8 significant bits) the solution is a few 1e-3 of its norm from the double one, and
// as CG's preconditioner on the same matrix it still converges in a few products (the float copy:
// one).
TEST(SinglePrecisionFactor, InBfloat16PreconditionsTheSameSystem) {
  const Eigen::SparseMatrix<double> A = testing::swinging_cloth_hessian();
  SparseCholesky cholesky;
  ASSERT_TRUE(cholesky.factorize_matrix(A));
  SinglePrecisionFactor compact, single;
  compact.assign(cholesky, SinglePrecisionFactor::Storage::BFloat16);
  single.assign(cholesky);
  EXPECT_EQ(compact.storage(), SinglePrecisionFactor::Storage::BFloat16);
  EXPECT_EQ(single.storage(), SinglePrecisionFactor::Storage::Float);
  const VecX b = VecX::Random(A.rows());
  VecX in_doubles = b, in_bfloat16 = b;
  cholesky.solve_in_place(in_doubles.data(), static_cast<int>(b.size()), 1);
  compact.solve_in_place(in_bfloat16);
  const double distance = (in_bfloat16 - in_doubles).norm() / in_doubles.norm();
  EXPECT_LT(distance, 2e-2);
  EXPECT_GT(distance, 1e-5);  // really the coarser values: float's copy is 1e-7 away
  // Preconditioned CG on A x = b to 1e-8.
  VecX x;
  const int products = testing::pcg_iterations(
      A, b, [&](VecX& r) { compact.solve_in_place(r); }, 1e-8, 50, &x);
  EXPECT_LE(products, 8);
  EXPECT_LT((A * x - b).norm(), 1e-7 * b.norm());
}

TEST(SinglePrecisionFactor, NeedsASupernodalFactor) {
  SparseCholesky none, simplicial(SparseCholesky::Method::Simplicial);
  ASSERT_TRUE(simplicial.factorize_matrix(testing::swinging_cloth_hessian()));
  SinglePrecisionFactor single;
  EXPECT_TRUE(testing::throws_error([&] { single.assign(none); }, "needs a supernodal LL^T factor"));
  EXPECT_TRUE(testing::throws_error([&] { single.assign(simplicial); }, "needs a supernodal LL^T factor"));
}

}  // namespace
}  // namespace fnopt
