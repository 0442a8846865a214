// The prefactored quasi-Newton method and its matrix: the matrix is the trace construction of
// the projected Hessian and does not change when the cloth is rotated; one iteration is exact on
// a quadratic whose Hessian is the matrix; handles never move; it converges to Newton's step;
// the factor is rebuilt only when the scene changes; bad parameters are one-line errors.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/cloth_step.hpp"

namespace fnopt {
namespace {

std::vector<int> all_free(const Grid& grid) {
  std::vector<int> index(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) index[k] = k;
  return index;
}

// A crumpled state: the rest pose with random displacements of a third of a cell.
VecX crumpled(const Grid& grid, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, grid.spacing / 3.0);
  VecX x = grid.rest_positions();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += normal(random);
  return x;
}

Mat3 rotation(double angle, const Vec3& axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

// The naive reference: the objective's own projected Hessian at x, each 3x3 elastic block
// replaced by trace(B) I3, the inertia diagonal kept.
Eigen::MatrixXd naive_isotropic(BackwardEulerObjective& objective, const VecX& x) {
  const Grid& grid = objective.grid();
  objective.begin_step(x, VecX::Zero(grid.dof_count()));  // then x(a = 0) = x
  Eigen::MatrixXd H(objective.hessian(VecX::Zero(grid.dof_count()), all_free(grid), true));
  for (int k = 0; k < grid.vertex_count(); ++k)
    H.block<3, 3>(3 * k, 3 * k) -= objective.inertia_weight(k) * Mat3::Identity();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(H.rows(), H.cols());
  for (int i = 0; i < grid.vertex_count(); ++i)
    for (int j = 0; j < grid.vertex_count(); ++j)
      A.block<3, 3>(3 * i, 3 * j) = H.block<3, 3>(3 * i, 3 * j).trace() * Mat3::Identity();
  for (int k = 0; k < grid.vertex_count(); ++k)
    A.block<3, 3>(3 * k, 3 * k) += objective.inertia_weight(k) * Mat3::Identity();
  return A;
}

TEST(PqnMatrix, IsotropicIsTheTraceOfEachBlockOfTheProjectedHessian) {
  const Grid grid = Grid::make(7, 6, 1.0);
  Material material;
  material.bend = 1e-3;  // so that bending weighs in the comparison
  BackwardEulerObjective objective(grid, material, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const VecX x = crumpled(grid, 3);
  const Eigen::MatrixXd expected = naive_isotropic(objective, x);
  const Eigen::MatrixXd built(build_pqn_matrix(objective, all_free(grid), x).expanded());
  EXPECT_LT((built - expected).norm(), 1e-12 * expected.norm());
}

TEST(PqnMatrix, DoesNotChangeWhenTheClothIsRotated) {
  const Grid grid = Grid::make(6, 8, 1.0);
  const BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const std::vector<int> free_index = all_free(grid);
  const VecX x = crumpled(grid, 11);
  const Mat3 R = rotation(1.1, Vec3(0.3, -1.0, 0.5));
  VecX rotated(x.size());
  for (int k = 0; k < grid.vertex_count(); ++k) rotated.segment<3>(3 * k) = R * x.segment<3>(3 * k) + Vec3(0.2, -1, 3);
  const Eigen::MatrixXd A(build_pqn_matrix(objective, free_index, x).expanded());
  const Eigen::MatrixXd B(build_pqn_matrix(objective, free_index, rotated).expanded());
  EXPECT_LT((A - B).norm() / A.norm(), 1e-12);
}

TEST(Pqn, OneIterationIsExactOnAQuadraticWhoseHessianIsTheMatrix) {
  const Grid grid = Grid::make(9, 7, 1.0);
  const BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const PqnMatrix matrix = build_pqn_matrix(objective, all_free(grid), crumpled(grid, 5));
  const Eigen::SparseMatrix<double> A = matrix.expanded();
  VecX b(A.rows());
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1e-4);
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = normal(random);
  FunctionSmoothProblem quadratic(static_cast<int>(A.rows()), [&](const VecX& x, VecX* g) {
    const VecX Ax = A * x;
    if (g) *g = Ax - b;
    return 0.5 * x.dot(Ax) - b.dot(x);
  });
  PqnOptimizer pqn;
  pqn.use_matrix(matrix);
  VecX x = VecX::Zero(A.rows()), g;
  double value = quadratic.value_gradient(x, g);
  const double g0 = g.norm();
  pqn.begin(quadratic, x, value, g);
  ASSERT_FALSE(pqn.step(quadratic, x, value, g).has_value());
  const VecX exact = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(A).solve(b);
  EXPECT_LT((x - exact).norm(), 1e-10 * exact.norm());
  EXPECT_LT(g.norm(), 1e-10 * g0);
}

TEST(PqnMatrix, QuadraticFormIsQTransposeAQOverTheFreeDofs) {
  // Against the expanded matrix on the free dofs; whatever the fixed dofs hold does not count.
  const Grid grid = Grid::make(7, 6, 1.0);
  const BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, 5, 20});
  std::mt19937 random(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  VecX q(grid.dof_count());
  for (Eigen::Index i = 0; i < q.size(); ++i) q[i] = normal(random);
  const PqnMatrix matrix = build_pqn_matrix(objective, handles.free_index(), crumpled(grid, 2));
  VecX q_free(matrix.expanded().rows());
  for (int v = 0; v < grid.vertex_count(); ++v)
    if (const int f = handles.free_index()[v]; f >= 0) q_free.segment<3>(3 * f) = q.segment<3>(3 * v);
  const double expected = q_free.dot(matrix.expanded() * q_free);
  PqnFactor factor;
  ASSERT_TRUE(factor.factorize(matrix));
  EXPECT_NEAR(factor.quadratic_form(q), expected, 1e-12 * std::abs(expected));
}

TEST(Pqn, APairAddedFromOutsideShapesTheNextIteration) {
  // f = 1/2 x^T H x with H != A: from x0 the first iteration along -A^-1 g does not reach the
  // minimum. Given the pair of the step x0 -> 0 (s = -x0, y = -H x0), the two-loop direction
  // satisfies H_1 y = s, so the next iteration lands on the minimum exactly.
  const Grid grid = Grid::make(6, 5, 1.0);
  const BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const PqnMatrix matrix = build_pqn_matrix(objective, all_free(grid), grid.rest_positions());
  const Eigen::SparseMatrix<double> A = matrix.expanded();
  const Eigen::MatrixXd H = Eigen::MatrixXd(A) * 1.5 + Eigen::MatrixXd::Identity(A.rows(), A.cols()) * 1e-7;
  FunctionSmoothProblem quadratic(static_cast<int>(A.rows()), [&](const VecX& x, VecX* g) {
    const VecX Hx = H * x;
    if (g) *g = Hx;
    return 0.5 * x.dot(Hx);
  });
  VecX x0(A.rows());
  std::mt19937 random(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index i = 0; i < x0.size(); ++i) x0[i] = normal(random);
  for (bool with_pair : {false, true}) {
    PqnOptimizer pqn;
    pqn.use_matrix(matrix);
    VecX x = x0, g;
    double value = quadratic.value_gradient(x, g);
    pqn.begin(quadratic, x, value, g);
    if (with_pair) {
      ASSERT_TRUE(pqn.add_pair(x0, g, VecX::Zero(x0.size()), VecX::Zero(x0.size())));
    }
    ASSERT_FALSE(pqn.step(quadratic, x, value, g).has_value());
    if (with_pair)
      EXPECT_LT(x.norm(), 1e-9 * x0.norm());
    else
      EXPECT_GT(x.norm(), 0.1 * x0.norm()) << "A must be a poor model of H for this test to mean anything";
  }
  PqnOptimizer pqn;
  pqn.use_matrix(matrix);
  VecX g0 = H * x0;
  pqn.begin(quadratic, x0, quadratic.value(x0), g0);
  EXPECT_FALSE(pqn.add_pair(x0, g0, x0 + g0, g0 - H * g0)) << "a pair of negative curvature is not kept";
}

TEST(Pqn, NeverMovesAHandleAndConvergesToTheNewtonStep) {
  ClothStep step;
  NewtonOptimizer newton;
  VecX a_star = step.a;
  const double best = solve_step(newton, step.problem, a_star, NewtonOptimizer::reference_solve_options()).value;
  PqnOptimizer pqn;
  double previous_error = INFINITY, step_error = INFINITY;
  for (int budget : {5, 20, 80}) {
    VecX a = step.a;
    const InnerSolveResult r = solve_step(pqn, step.problem, a, {budget, 0.0});
    for (int h : step.handles.fixed_vertices()) EXPECT_EQ(a.segment<3>(3 * h), step.a.segment<3>(3 * h)) << h;
    const double error = (a - a_star).norm() / (step.a - a_star).norm();
    step_error = (r.value - best) / (r.initial_value - best);
    std::printf("pqn %2d iterations: per-step error %.3g, |a - a*| / |a0 - a*| = %.3g (%s)\n", budget, step_error,
                error, to_string(r.status));
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
  // A linear tail, as the isotropic matrix is stiffer out of plane than the cloth at rest.
  EXPECT_LT(step_error, 1e-4);
  EXPECT_LT(previous_error, 2e-2);
}

TEST(Pqn, RefactorizesOnlyWhenTheSceneChanges) {
  ClothStep step;
  PqnOptimizer pqn;
  auto solve = [&](StepProblem& problem) {
    VecX a = step.a;
    solve_step(pqn, problem, a, {3, 0.0});
  };
  solve(step.problem);
  solve(step.problem);  // the next time step of the same scene
  EXPECT_EQ(pqn.factorizations(), 1);
  BackwardEulerObjective same(step.grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));  // a new rollout
  same.begin_step(step.x, step.v);
  StepProblem same_problem(same, step.handles);
  solve(same_problem);
  EXPECT_EQ(pqn.factorizations(), 1);
  BackwardEulerObjective smaller_dt(step.grid, Material{}, 1.0 / 120.0, Vec3(0, 0, -9.81));
  smaller_dt.begin_step(step.x, step.v);
  StepProblem dt_problem(smaller_dt, step.handles);
  solve(dt_problem);
  EXPECT_EQ(pqn.factorizations(), 2);
  Material stiffer;
  stiffer.stretch *= 10.0;
  BackwardEulerObjective stiff(step.grid, stiffer, 1.0 / 120.0, Vec3(0, 0, -9.81));
  stiff.begin_step(step.x, step.v);
  StepProblem stiff_problem(stiff, step.handles);
  solve(stiff_problem);
  EXPECT_EQ(pqn.factorizations(), 3);
  const DirichletSet one_handle(step.grid.vertex_count(), {0});
  StepProblem handle_problem(stiff, one_handle);
  solve(handle_problem);
  EXPECT_EQ(pqn.factorizations(), 4);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Pqn, BadParametersAreOneLineErrors) {
  PqnParams history;
  history.history = -1;
  EXPECT_EQ(error_of([&] { PqnOptimizer{history}; }), "pqn.history: must lie in [0, 1000]");
  PqnParams armijo;
  armijo.line_search.armijo = 0.7;
  EXPECT_EQ(error_of([&] { PqnOptimizer{armijo}; }), "pqn.armijo: must lie in (0, 0.5)");
  PqnParams trials;
  trials.line_search.max_trials = 0;
  EXPECT_EQ(error_of([&] { PqnOptimizer{trials}; }), "pqn.max_backtracks: must be positive");
}

}  // namespace
}  // namespace fnopt
