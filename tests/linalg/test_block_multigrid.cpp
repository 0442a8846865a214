// The multigrid V-cycle against a naive two-grid method written with dense matrices (bilinear
// prolongation by grid position, Galerkin product R^T A R, block Gauss–Seidel), its symmetry and
// definiteness (what CG's preconditioner needs), its strength as a preconditioner on a cloth
// Hessian, the exact solve when no level is coarsened, and its errors on bad input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/linalg/block_multigrid.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/preconditioned_cg.hpp"

namespace fnopt {
namespace {

// The projected step Hessian of a cloth swinging sideways, two corners held (SPD: it holds the mass).
struct ClothMatrix {
  Grid grid;
  DirichletSet handles;
  Eigen::SparseMatrix<double> A;
};

// Held at two corners, or along its first `held_rows` rows.
ClothMatrix cloth_matrix(int rows, int cols, int held_rows = 0) {
  const Grid grid = Grid::make(rows, cols, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  VecX v = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k] = 1.5 * (k % grid.cols) / grid.cols;
  objective.begin_step(grid.rest_positions(), v);
  std::vector<int> held = {0, grid.cols - 1};
  for (int k = grid.cols; k < held_rows * grid.cols; ++k) held.push_back(k);
  if (held_rows > 0)
    for (int k = 1; k + 1 < grid.cols; ++k) held.push_back(k);
  DirichletSet handles(grid.vertex_count(), held);
  VecX a = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) a[3 * k + 2] = -5.0 * std::sin(0.7 * k);  // a crumpled trial step
  Eigen::SparseMatrix<double> A = objective.hessian(a, handles.free_index(), true);
  return {grid, handles, A};
}

// A line of n grid points keeps every other one and its last: coarse point k at min(2k, n - 1).
int coarse_points(int n) { return n % 2 == 0 ? n / 2 + 1 : (n + 1) / 2; }

// Linear interpolation weight of fine point i from coarse point k, by their positions.
double hat(int i, int k, int n) {
  auto position = [n](int c) { return std::min(2 * c, n - 1); };
  const int p = position(k);
  if (i == p) return 1.0;
  if (i < p && k > 0 && i > position(k - 1)) return 1.0 - double(p - i) / (p - position(k - 1));
  if (i > p && k + 1 < coarse_points(n) && i < position(k + 1)) return 1.0 - double(i - p) / (position(k + 1) - p);
  return 0.0;
}

// One two-grid cycle with dense matrices: `sweeps` forward block Gauss–Seidel sweeps from 0, the
// coarse correction R (R^T A R)^-1 R^T (b - A x), as many backward sweeps.
VecX naive_two_grid(const ClothMatrix& m, const VecX& b, int sweeps) {
  const Eigen::MatrixXd A(m.A);
  const int n = static_cast<int>(A.rows()) / 3;
  const int coarse_rows = coarse_points(m.grid.rows), coarse_cols = coarse_points(m.grid.cols);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(A.rows(), 3 * coarse_rows * coarse_cols);
  for (int v = 0; v < m.grid.vertex_count(); ++v) {
    const int f = m.handles.free_index()[v];
    if (f < 0) continue;
    for (int K = 0; K < coarse_rows; ++K)
      for (int L = 0; L < coarse_cols; ++L) {
        const double w = hat(v / m.grid.cols, K, m.grid.rows) * hat(v % m.grid.cols, L, m.grid.cols);
        for (int c = 0; c < 3; ++c) R(3 * f + c, 3 * (K * coarse_cols + L) + c) = w;
      }
  }
  // A coarse vertex whose support holds no free vertex is no unknown: drop its (zero) columns.
  std::vector<int> kept;
  for (int c = 0; c < R.cols(); ++c)
    if (R.col(c).squaredNorm() > 0.0) kept.push_back(c);
  R = R(Eigen::all, kept).eval();
  auto sweep = [&](VecX& x, bool forward) {
    for (int t = 0; t < n; ++t) {
      const int i = forward ? t : n - 1 - t;
      const Eigen::Vector3d s =
          b.segment<3>(3 * i) - A.middleRows<3>(3 * i) * x + A.block<3, 3>(3 * i, 3 * i) * x.segment<3>(3 * i);
      x.segment<3>(3 * i) = A.block<3, 3>(3 * i, 3 * i).llt().solve(s);
    }
  };
  VecX x = VecX::Zero(b.size());
  for (int s = 0; s < sweeps; ++s) sweep(x, true);
  const Eigen::MatrixXd coarse = R.transpose() * A * R;
  x += R * coarse.llt().solve(R.transpose() * (b - A * x));
  for (int s = 0; s < sweeps; ++s) sweep(x, false);
  return x;
}

TEST(BlockMultigrid, TwoLevelsAreTheNaiveTwoGridCycle) {
  // 10 x 11: an even line coarsens to 0, 2, ..., 8 and its last point 9; an odd one to 0, 2, ..., 10.
  // Held at two corners, and along its first two rows (then the coarse grid's first row has no
  // free vertex under it and is no unknown).
  for (int held_rows : {0, 2})
    for (int sweeps : {1, 2}) {  // the default, and more sweeps than one
      const ClothMatrix m = cloth_matrix(10, 11, held_rows);
      BlockMultigridParams params;
      params.smoothing_sweeps = sweeps;
      params.coarsest_dofs = 120;  // at most 108 unknown dofs on the 6 x 6 coarse grid: two levels
      BlockMultigrid multigrid(params);
      ASSERT_TRUE(multigrid.assign(m.A, m.grid, m.handles.free_index()));
      ASSERT_EQ(multigrid.level_count(), 2);
      for (int trial = 0; trial < 3; ++trial) {
        const VecX b = VecX::Random(m.A.rows());
        VecX cycle = b;
        multigrid.solve_in_place(cycle);
        const VecX naive = naive_two_grid(m, b, sweeps);
        EXPECT_LT((cycle - naive).norm(), 1e-5 * naive.norm()) << sweeps << " sweeps, " << held_rows << " rows held";
      }
    }
}

TEST(BlockMultigrid, IsASymmetricPositiveDefiniteOperator) {
  const ClothMatrix m = cloth_matrix(33, 40);
  BlockMultigrid multigrid;
  ASSERT_TRUE(multigrid.assign(m.A, m.grid, m.handles.free_index()));
  EXPECT_GE(multigrid.level_count(), 3);
  for (int trial = 0; trial < 5; ++trial) {
    const VecX u = VecX::Random(m.A.rows()), v = VecX::Random(m.A.rows());
    VecX Bu = u, Bv = v;
    multigrid.solve_in_place(Bu);
    multigrid.solve_in_place(Bv);
    EXPECT_NEAR(v.dot(Bu), u.dot(Bv), 1e-5 * std::sqrt(u.dot(Bu) * v.dot(Bv)));
    EXPECT_GT(u.dot(Bu), 0.0);
  }
}

TEST(BlockMultigrid, PreconditionsAClothHessianAlikeOnEveryGrid) {
  int previous = 0;
  for (int n : {24, 48, 96}) {
    const ClothMatrix m = cloth_matrix(n, n);
    BlockMultigrid multigrid;
    ASSERT_TRUE(multigrid.assign(m.A, m.grid, m.handles.free_index()));
    const VecX b = VecX::Random(m.A.rows());
    const int with = testing::pcg_iterations(
        m.A, b, [&](VecX& r) { multigrid.solve_in_place(r); }, 1e-6, 2000);
    const int jacobi = testing::pcg_iterations(
        m.A, b, [&](VecX& r) { r.array() /= VecX(m.A.diagonal()).array(); }, 1e-6, 2000);
    std::printf("%d^2: CG iterations to 1e-6, V-cycle %d, Jacobi %d\n", n, with, jacobi);
    EXPECT_LT(4 * with, jacobi);
    if (previous > 0) {
      EXPECT_LE(with, previous + 5);  // about as many on every grid
    }
    previous = with;
  }
}

TEST(BlockMultigrid, SolvesExactlyWhenNothingIsCoarsened) {
  const ClothMatrix m = cloth_matrix(8, 9);
  BlockMultigridParams params;
  params.coarsest_dofs = static_cast<int>(m.A.rows());
  BlockMultigrid multigrid(params);
  ASSERT_TRUE(multigrid.assign(m.A, m.grid, m.handles.free_index()));
  EXPECT_EQ(multigrid.level_count(), 1);
  const VecX b = VecX::Random(m.A.rows());
  VecX x = b;
  multigrid.solve_in_place(x);
  EXPECT_LT((m.A * x - b).norm(), 1e-5 * b.norm());
}

TEST(BlockMultigrid, NewValuesOnAKeptPatternRebuildTheLevels) {
  const ClothMatrix m = cloth_matrix(20, 20);
  BlockMultigrid multigrid;
  ASSERT_TRUE(multigrid.assign(m.A, m.grid, m.handles.free_index(), 7));
  const VecX b = VecX::Random(m.A.rows());
  VecX once = b, twice = b;
  multigrid.solve_in_place(once);
  const Eigen::SparseMatrix<double> doubled = 2.0 * m.A;
  ASSERT_TRUE(multigrid.assign(doubled, m.grid, m.handles.free_index(), 7));
  multigrid.solve_in_place(twice);
  EXPECT_LT((2.0 * twice - once).norm(), 1e-5 * once.norm());
}

TEST(BlockMultigrid, RejectsWhatIsNotItsMatrix) {
  const ClothMatrix m = cloth_matrix(8, 8);
  BlockMultigrid multigrid;
  const Grid other = Grid::make(8, 9, 1.0);
  EXPECT_TRUE(testing::throws_error([&] { multigrid.assign(m.A, other, m.handles.free_index()); },
                                    "free index does not match the grid"));
  Eigen::SparseMatrix<double> scalar(62, 62);  // one dof per free vertex
  scalar.setIdentity();
  EXPECT_TRUE(testing::throws_error([&] { multigrid.assign(scalar, m.grid, m.handles.free_index()); },
                                    "not 3 dofs per free vertex"));
  Eigen::SparseMatrix<double> diagonal(m.A.rows(), m.A.cols());  // scalar entries, not 3x3 blocks
  diagonal.setIdentity();
  EXPECT_TRUE(testing::throws_error([&] { multigrid.assign(diagonal, m.grid, m.handles.free_index()); },
                                    "not made of 3x3 blocks"));
  EXPECT_TRUE(testing::throws_error(
      [] {
        BlockMultigrid(BlockMultigridParams{0, 400});
      },
      "multigrid.smoothing_sweeps"));
  EXPECT_TRUE(testing::throws_error([] { BlockMultigrid(BlockMultigridParams{1, 2}); }, "multigrid.coarsest_dofs"));
}

}  // namespace
}  // namespace fnopt
