// The lower-triangle block product against Eigen's product with the whole matrix, on a cloth's
// exact (indefinite) Hessian with handles; new values on a kept pattern; a new pattern; bad input.
#include <gtest/gtest.h>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/optimizer/symmetric_block_matrix.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

struct ClothHessian {
  Eigen::SparseMatrix<double> H;
  long pattern;
};

// The exact Hessian of a crumpled trial step on a rows x cols cloth held at two corners.
ClothHessian cloth_hessian(int rows, int cols, double crumple) {
  const Grid grid = Grid::make(rows, cols, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  VecX a = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) a[3 * k + 2] = -crumple * std::sin(0.7 * k);
  return {objective.hessian(a, handles.free_index(), false), objective.hessian_pattern_id()};
}

double relative_product_error(const SymmetricBlockMatrix& S, const Eigen::SparseMatrix<double>& H, const VecX& x) {
  VecX y;
  S.multiply(x, y);
  const VecX expected = H * x;
  return (y - expected).norm() / expected.norm();
}

TEST(SymmetricBlockMatrix, ProductEqualsTheWholeMatrix) {
  for (const auto& [rows, cols] : {std::pair{6, 6}, std::pair{9, 14}, std::pair{32, 32}}) {
    const ClothHessian h = cloth_hessian(rows, cols, 5.0);
    SymmetricBlockMatrix S;
    S.assign(h.H, h.pattern);
    ASSERT_EQ(S.rows(), h.H.rows());
    for (int trial = 0; trial < 3; ++trial) EXPECT_LT(relative_product_error(S, h.H, VecX::Random(h.H.rows())), 1e-14);
  }
}

TEST(SymmetricBlockMatrix, NewValuesOnAKeptPattern) {
  ClothHessian h = cloth_hessian(12, 10, 5.0);
  SymmetricBlockMatrix S;
  S.assign(h.H, h.pattern);
  // The same pattern, other values (the pattern id is kept): only the values are copied.
  h.H.coeffs() = h.H.coeffs().array() * (1.0 + 0.5 * Eigen::ArrayXd::Random(h.H.nonZeros()));
  h.H = Eigen::SparseMatrix<double>(h.H.transpose()) + h.H;  // symmetric again, the same pattern
  S.assign(h.H, h.pattern);
  EXPECT_LT(relative_product_error(S, h.H, VecX::Random(h.H.rows())), 1e-14);
  // Another pattern (another grid) with a new id is read again.
  const ClothHessian other = cloth_hessian(7, 8, 2.0);
  S.assign(other.H, other.pattern);
  EXPECT_EQ(S.rows(), other.H.rows());
  EXPECT_LT(relative_product_error(S, other.H, VecX::Random(other.H.rows())), 1e-14);
}

TEST(SymmetricBlockMatrix, RefusesAMatrixNotOf3x3Blocks) {
  Eigen::SparseMatrix<double> A(4, 4);
  A.setIdentity();
  SymmetricBlockMatrix S;
  EXPECT_TRUE(testing::throws_error([&] { S.assign(A); }, "the matrix is not square in 3x3 blocks"));
  Eigen::SparseMatrix<double> B(6, 6);
  B.setIdentity();  // 3x3 shape, but a column holds 1 entry, not a block's 3
  EXPECT_TRUE(testing::throws_error([&] { S.assign(B); }, "the matrix is not made of 3x3 blocks"));
}

}  // namespace
}  // namespace fnopt
