// The inertia read off an LDL^T factorisation agrees with a dense eigen-decomposition: on random
// sparse symmetric matrices with a chosen number of negative eigenvalues, and on the exact
// Hessian of a compressed cloth's step; its direction of negative curvature curves downward.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/linalg/matrix_inertia.hpp>

namespace fnopt {
namespace {

int dense_negative_count(const Eigen::SparseMatrix<double>& a) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(Eigen::MatrixXd(a), Eigen::EigenvaluesOnly);
  return static_cast<int>((eigen.eigenvalues().array() < 0.0).count());
}

TEST(MatrixInertia, CountsTheNegativeEigenvaluesOfRandomSparseMatrices) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const int n = 60;
  for (int negative : {0, 1, 7, 30}) {
    // A banded symmetric matrix plus a diagonal that makes `negative` eigenvalues clearly negative.
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = i; j < std::min(n, i + 4); ++j) dense(i, j) = dense(j, i) = 0.3 * normal(rng);
    for (int i = 0; i < n; ++i) dense(i, i) += (i * 37 % n < negative ? -3.0 : 3.0);
    const Eigen::SparseMatrix<double> a = dense.sparseView();
    EXPECT_EQ(dense_negative_count(a), negative);
    EXPECT_EQ(negative_eigenvalue_count(a), negative) << negative << " negative eigenvalues";
    // The direction from the same factorisation has negative curvature exactly where some
    // eigenvalue is negative.
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    EXPECT_EQ(negative_curvature_direction(a, z), negative);
    if (negative > 0)
      EXPECT_LT(z.dot(a * z), 0.0) << negative << " negative eigenvalues";
    else
      EXPECT_EQ(z.norm(), 0.0) << "no direction at a positive definite matrix";
  }
  EXPECT_EQ(negative_eigenvalue_count(Eigen::SparseMatrix<double>(Eigen::MatrixXd::Zero(3, 3).sparseView())), -1);
}

TEST(MatrixInertia, AgreesWithTheDenseSpectrumOnACompressedClothsHessian) {
  // A 6 x 6 cloth squeezed to 80 % of its width: its compressed springs give the step's exact
  // Hessian negative curvature that the inertia term does not cover at a large time step.
  const Grid grid = Grid::make(6, 6, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 0.1, Vec3::Zero());
  VecX x = grid.rest_positions();
  for (int k = 0; k < grid.vertex_count(); ++k) x(3 * k) *= 0.8;
  objective.begin_step(x, VecX::Zero(grid.dof_count()));
  std::vector<int> free_index(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) free_index[k] = k;
  const Eigen::SparseMatrix<double>& h = objective.hessian(VecX::Zero(grid.dof_count()), free_index, false);
  const int expected = dense_negative_count(h);
  EXPECT_GT(expected, 0);
  EXPECT_EQ(negative_eigenvalue_count(h), expected);
  EXPECT_EQ(negative_eigenvalue_count(objective.hessian(VecX::Zero(grid.dof_count()), free_index, true)), 0);
}

}  // namespace
}  // namespace fnopt
