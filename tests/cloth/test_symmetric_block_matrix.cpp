// The lower-triangle block matrix the assembly fills against the whole CSC matrix of the same
// Hessian: the same blocks bit for bit (the same sums in the same order) and the same products, on a
// cloth's exact (indefinite) and projected Hessians with handles and self-repulsion; a kept pattern
// with new values; a malformed pattern; the product on several threads the same bit for bit.
#include <gtest/gtest.h>
#include <omp.h>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/cloth/symmetric_block_matrix.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

// A crumpled trial step on a rows x cols cloth held at two corners.
VecX crumpled_step(const Grid& grid, double crumple) {
  VecX a = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) a[3 * k + 2] = -crumple * std::sin(0.7 * k);
  return a;
}

// A's products with the unit vectors, column by column.
Eigen::MatrixXd dense(const SymmetricBlockMatrix& A) {
  Eigen::MatrixXd D(A.rows(), A.rows());
  VecX e = VecX::Zero(A.rows()), column;
  for (Eigen::Index j = 0; j < A.rows(); ++j) {
    e[j] = 1.0;
    A.multiply(e, column);
    D.col(j) = column;
    e[j] = 0.0;
  }
  return D;
}

TEST(SymmetricBlockMatrix, HoldsTheAssembledHessianExactly) {
  for (const auto& [rows, cols] : {std::pair{6, 6}, std::pair{9, 14}, std::pair{20, 20}})
    for (const bool project : {false, true}) {
      const Grid grid = Grid::make(rows, cols, 1.0);
      BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
      objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
      const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
      const VecX a = crumpled_step(grid, 5.0);
      const Eigen::MatrixXd whole = Eigen::MatrixXd(objective.hessian(a, handles.free_index(), project));
      const SymmetricBlockMatrix& lower = objective.hessian_blocks(a, handles.free_index(), project);
      ASSERT_EQ(lower.rows(), whole.rows());
      EXPECT_EQ(dense(lower), whole) << rows << "x" << cols << " project " << project;
      const VecX x = VecX::Random(whole.rows());
      VecX y;
      lower.multiply(x, y);
      EXPECT_LT((y - whole * x).norm(), 1e-14 * (whole * x).norm());
    }
}

TEST(SymmetricBlockMatrix, ProductIsTheSameOnAnyNumberOfThreads) {
  // 48 x 48 vertices, two held: 2302 block rows, enough for the parallel path.
  const Grid grid = Grid::make(48, 48, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  const VecX a = crumpled_step(grid, 5.0);
  const Eigen::SparseMatrix<double> whole = objective.hessian(a, handles.free_index(), false);
  const SymmetricBlockMatrix& lower = objective.hessian_blocks(a, handles.free_index(), false);
  ASSERT_GE(lower.rows() / 3, SymmetricBlockMatrix::kParallelRows);
  const VecX x = VecX::Random(lower.rows());
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  VecX serial;
  lower.multiply(x, serial);
  EXPECT_LT((serial - whole * x).norm(), 1e-14 * (whole * x).norm());
  for (const int threads : {2, 3, 4, 7, 2}) {
    omp_set_num_threads(threads);
    VecX parallel = VecX::Constant(lower.rows(), 1.0);  // not zero: the product must set every entry
    lower.multiply(x, parallel);
    EXPECT_TRUE(parallel == serial) << threads << " threads: max difference "
                                    << (parallel - serial).cwiseAbs().maxCoeff();
  }
  omp_set_num_threads(threads_before);
}

TEST(SymmetricBlockMatrix, FollowsNewValuesAndRepulsionPairs) {
  const Grid grid = Grid::make(12, 10, 1.0);
  Material material;
  material.repulsion = true;
  BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1});
  // A cloth folded onto itself: the repulsion term adds pairs, and the pattern changes with them.
  VecX x = grid.rest_positions();
  const double width = grid.spacing * (grid.cols - 1);
  for (int k = 0; k < grid.vertex_count(); ++k)
    if (x[3 * k] > 0.5 * width) {
      x[3 * k] = width - x[3 * k];
      x[3 * k + 2] = 0.2 * grid.spacing;
    }
  for (const VecX& start : {grid.rest_positions(), x}) {
    objective.begin_step(start, VecX::Zero(grid.dof_count()));
    for (const double crumple : {1.0, 3.0}) {
      const VecX a = crumpled_step(grid, crumple);
      const Eigen::MatrixXd whole = Eigen::MatrixXd(objective.hessian(a, handles.free_index(), false));
      EXPECT_EQ(dense(objective.hessian_blocks(a, handles.free_index(), false)), whole);
    }
  }
}

TEST(SymmetricBlockMatrix, RefusesAMalformedPattern) {
  SymmetricBlockMatrix S;
  EXPECT_TRUE(testing::throws_error([&] { S.set_pattern({0, 1, 3}, {0, 0}); }, "row starts do not span the columns"));
  EXPECT_TRUE(testing::throws_error(
      [&] {
        S.set_pattern({0, 1, 2}, {0, 0});
      },
      "a row does not end with its diagonal block"));
  EXPECT_TRUE(testing::throws_error(
      [&] {
        S.set_pattern({0, 1, 2, 5}, {0, 1, 1, 0, 2});
      },
      "a row's columns are not increasing and left of the diagonal"));
  S.set_pattern({0, 1, 3}, {0, 0, 1});
  EXPECT_EQ(S.rows(), 6);
}

}  // namespace
}  // namespace fnopt
