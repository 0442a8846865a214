// The assembled objective: gradient and sparse Hessian against finite differences on a small
// deformed grid, Dirichlet restriction of the Hessian, masses, stencil counts, grid units.
#include <gtest/gtest.h>

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <random>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/cloth/lumped_mass.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

struct Fixture {
  Grid grid = Grid::make(5, 4, 0.3);
  Material material{30.0, 3.0, 2e-3, 0.187, 0.5};
  double dt = 1.0 / 60.0;
  BackwardEulerObjective objective{grid, material, dt, Vec3(0.0, 0.0, -9.81)};
  VecX a;

  Fixture() {
    std::mt19937 rng(11);
    std::normal_distribution<double> normal(0.0, 1.0);
    VecX x = grid.rest_positions(), v(grid.dof_count());
    for (int i = 0; i < x.size(); ++i) {
      x[i] += 0.2 * grid.spacing * normal(rng);
      v[i] = 0.3 * normal(rng);
    }
    objective.begin_step(x, v);
    a.resize(grid.dof_count());
    for (int i = 0; i < a.size(); ++i) a[i] = 20.0 * normal(rng);
  }
};

TEST(BackwardEulerObjective, GradientMatchesFiniteDifferences) {
  Fixture f;
  VecX g;
  const double value = f.objective.value_gradient(f.a, g);
  EXPECT_NEAR(value, f.objective.value(f.a), 1e-14 * std::abs(value));
  ASSERT_GT(g.norm(), 0.0);
  const VecX fd = testing::central_gradient([&](const VecX& a) { return f.objective.value(a); }, f.a, 1e-4);
  for (int i = 0; i < f.a.size(); ++i) EXPECT_NEAR(g[i], fd[i], 1e-6 * g.norm()) << "dof " << i;
}

TEST(BackwardEulerObjective, SparseHessianMatchesFiniteDifferencesOfTheGradient) {
  Fixture f;
  std::vector<int> all_free(f.grid.vertex_count());
  for (int v = 0; v < f.grid.vertex_count(); ++v) all_free[v] = v;
  const Eigen::MatrixXd H = Eigen::MatrixXd(f.objective.hessian(f.a, all_free, false));
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const VecX& a) {
        VecX g;
        f.objective.value_gradient(a, g);
        return g;
      },
      f.a, 1e-3);
  EXPECT_LT((H - H_fd).norm(), 1e-6 * H.norm());
}

TEST(BackwardEulerObjective, DirichletHessianIsTheFreeBlock) {
  Fixture f;
  std::vector<int> all_free(f.grid.vertex_count()), some_free(f.grid.vertex_count());
  int next = 0;
  for (int v = 0; v < f.grid.vertex_count(); ++v) {
    all_free[v] = v;
    some_free[v] = (v == 0 || v == 3 || v == 9) ? -1 : next++;
  }
  const Eigen::MatrixXd full = Eigen::MatrixXd(f.objective.hessian(f.a, all_free, true));
  const Eigen::MatrixXd reduced = Eigen::MatrixXd(f.objective.hessian(f.a, some_free, true));
  ASSERT_EQ(reduced.rows(), 3 * next);
  for (int va = 0; va < f.grid.vertex_count(); ++va) {
    for (int vb = 0; vb < f.grid.vertex_count(); ++vb) {
      if (some_free[va] < 0 || some_free[vb] < 0) continue;
      EXPECT_EQ((reduced.block<3, 3>(3 * some_free[va], 3 * some_free[vb])), (full.block<3, 3>(3 * va, 3 * vb)));
    }
  }
}

TEST(BackwardEulerObjective, ProjectedHessianIsPositiveDefinite) {
  Fixture f;
  std::vector<int> all_free(f.grid.vertex_count());
  for (int v = 0; v < f.grid.vertex_count(); ++v) all_free[v] = v;
  const Eigen::MatrixXd H = Eigen::MatrixXd(f.objective.hessian(f.a, all_free, true));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff(), 0.0);
}

TEST(BackwardEulerObjective, ElasticForcesVanishAtRest) {
  const Grid grid = Grid::make(6, 9, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3::Zero());
  const VecX a = VecX::Zero(grid.dof_count());
  VecX g;
  EXPECT_NEAR(objective.value_gradient(a, g), 0.0, 1e-18);
  EXPECT_LT(g.norm(), 1e-18);
}

// The residual acceleration is a - f/m in m/s^2: a cloth at rest, not yet accelerated, leaves
// gravity unbalanced (9.81 at every vertex, whatever the grid or density); accelerated by
// gravity it leaves nothing, since the elastic forces vanish at rest and x(a) moves rigidly.
TEST(BackwardEulerObjective, ResidualAccelerationIsTheUnbalancedForcePerMass) {
  for (int n : {4, 9}) {
    const Grid grid = Grid::make(n, n + 2, 1.0);
    Material material;
    material.density = 0.37 * n;
    material.damping = 0.0;
    BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0.0, 0.0, -9.81));
    objective.begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
    VecX a = VecX::Zero(grid.dof_count()), g;
    objective.value_gradient(a, g);
    EXPECT_NEAR(objective.residual_acceleration(g), 9.81, 1e-9);
    for (int k = 0; k < grid.vertex_count(); ++k) a[3 * k + 2] = -9.81;
    objective.value_gradient(a, g);
    EXPECT_LT(objective.residual_acceleration(g), 1e-9);
  }
}

TEST(BackwardEulerObjective, OneThreadAndTwoGiveTheSameGradientAndHessians) {
  // The stencils are evaluated in parallel and scattered in one order: a reference does not depend on
  // the thread count it was solved with. A grid large enough for the parallel path (>= 2048 stencils).
  const Grid grid = Grid::make(40, 40, 0.05);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0.0, 0.0, -9.81));
  std::mt19937 rng(12);
  std::normal_distribution<double> normal(0.0, 1.0);
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count()), a(grid.dof_count());
  for (int i = 0; i < x.size(); ++i) x[i] += 0.2 * grid.spacing * normal(rng);
  for (int i = 0; i < a.size(); ++i) a[i] = 20.0 * normal(rng);
  objective.begin_step(x, v);
  std::vector<int> free_index(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) free_index[k] = k;
  const int threads = omp_get_max_threads();
  VecX gradient[2];
  double value[2];
  Eigen::SparseMatrix<double> exact[2], projected[2];
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run + 1);
    value[run] = objective.value_gradient(a, gradient[run]);
    exact[run] = objective.hessian(a, free_index, false);
    projected[run] = objective.hessian(a, free_index, true);
  }
  omp_set_num_threads(threads);
  EXPECT_EQ(gradient[0], gradient[1]);
  EXPECT_NEAR(value[0], value[1], 1e-12 * std::abs(value[0]));  // the parallel reduction's order may differ
  EXPECT_EQ(exact[0].coeffs().matrix(), exact[1].coeffs().matrix());
  EXPECT_EQ(projected[0].coeffs().matrix(), projected[1].coeffs().matrix());
}

TEST(BackwardEulerObjective, TheHessianPairIsTheTwoHessiansBitForBit) {
  // One evaluation per stencil for H's lower blocks and the projected P (the Newton reference's
  // rebuilds): the same values as the two separate assemblies, on one thread (each stencil added as
  // evaluated) and two (through the buffers), with handles and the repulsion term's default pair.
  const Grid grid = Grid::make(40, 40, 0.05);
  Material material;
  material.repulsion = true;
  BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0.0, 0.0, -9.81));
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count()), a(grid.dof_count());
  for (int i = 0; i < x.size(); ++i) x[i] += 0.3 * grid.spacing * normal(rng);
  for (int i = 0; i < a.size(); ++i) a[i] = 20.0 * normal(rng);
  objective.begin_step(x, v);
  const DirichletSet handles(grid.vertex_count(), {0, grid.cols - 1, 7 * grid.cols + 3});
  const std::vector<int>& free_index = handles.free_index();
  const int threads = omp_get_max_threads();
  for (int run = 1; run <= 2; ++run) {
    omp_set_num_threads(run);
    const std::vector<double> exact = objective.hessian_blocks(a, free_index, false).value_array();
    const Eigen::VectorXd projected = objective.hessian(a, free_index, true).coeffs();
    const BackwardEulerObjective::HessianPair pair = objective.hessian_pair(a, free_index);
    EXPECT_TRUE(pair.exact.value_array() == exact) << run << " threads";
    EXPECT_TRUE(pair.projected.coeffs().matrix() == projected) << run << " threads";
    const Eigen::VectorXd pair_projected = pair.projected.coeffs();
    EXPECT_GT((pair_projected - objective.hessian(a, free_index, false).coeffs().matrix()).norm(), 0.0);  // P != H
  }
  omp_set_num_threads(threads);
}

TEST(ClothTerms, StencilCountsAndMasses) {
  const Grid grid = Grid::make(5, 7, 1.0);
  EXPECT_EQ(grid_edges(grid).size(), 5u * 6 + 4u * 7);
  EXPECT_EQ(grid_shear_corners(grid).size(), 4u * 4 * 6);
  EXPECT_EQ(grid_bend_hinges(grid).size(), 5u * 5 + 3u * 7);
  const VecX m = lumped_masses(grid, 0.2);
  const double area = (grid.rows - 1) * grid.spacing * (grid.cols - 1) * grid.spacing;
  EXPECT_NEAR(m.sum(), 0.2 * area, 1e-15);
  EXPECT_DOUBLE_EQ(m[grid.index(0, 0)] * 4, m[grid.index(2, 3)]);
  EXPECT_DOUBLE_EQ(m[grid.index(0, 3)] * 2, m[grid.index(2, 3)]);
}

TEST(ClothTerms, ZeroCoefficientsBuildNoTerm) {
  const Grid grid = Grid::make(4, 4, 1.0);
  Material m;
  m.shear = 0.0;
  m.bend = 0.0;
  const auto terms = make_cloth_terms(grid, m);
  ASSERT_EQ(terms.size(), 1u);
  EXPECT_EQ(terms[0]->name(), "stretch");
}

TEST(Grid, RejectsTooSmallGridsAndBadSizes) {
  EXPECT_THROW(Grid::make(2, 2, 1.0), Error);
  EXPECT_THROW(Grid::make(3, 2, 1.0), Error);
  EXPECT_THROW(Grid::make(3, 3, 0.0), Error);
  EXPECT_THROW(Grid::make(3, 3, std::nan("")), Error);
  try {
    Grid::make(2, 5, 1.0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rows"), std::string::npos);
  }
}

TEST(Grid, NonSquareGridsKeepSquareCellsAndTheArcsimLayout) {
  const Grid grid = Grid::make(3, 5, 2.0);
  EXPECT_DOUBLE_EQ(grid.spacing, 0.5);
  const VecX x = grid.rest_positions();
  EXPECT_EQ(vertex(x, grid.index(2, 4)), Vec3(2.0, 0.0, -1.0));
  const auto faces = grid.triangles();
  ASSERT_EQ(faces.rows(), 2 * 2 * 4);
  EXPECT_EQ(faces.row(0), Eigen::RowVector3i(0, 1, 6));
  EXPECT_EQ(faces.row(1), Eigen::RowVector3i(0, 6, 5));
}

TEST(GridUnits, ScaleWithResolutionAsDerived) {
  Material m;
  const double dt = 1.0 / 60.0;
  const auto k32 = grid_unit_stiffness(Grid::make(32, 32, 1.0), m, dt, 9.81);
  const auto k63 = grid_unit_stiffness(Grid::make(63, 63, 1.0), m, dt, 9.81);
  EXPECT_NEAR(k63.stretch / k32.stretch, 4.0, 1e-12);  // h halves: k~_s x4
  EXPECT_NEAR(k63.bend / k32.bend, 16.0, 1e-12);       // k~_b x16
  EXPECT_NEAR(k32.stretch, m.stretch * dt * dt / (m.density / (31.0 * 31.0)), 1e-9);
}

TEST(Material, RejectsBadValuesNamingTheField) {
  Material m;
  m.density = -1.0;
  try {
    m.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("density: "), std::string::npos);
  }
  m = Material{};
  m.bend = std::nan("");
  EXPECT_THROW(m.validate(), Error);
  EXPECT_THROW(material_preset("no-such-material"), Error);
}

}  // namespace
}  // namespace fnopt
