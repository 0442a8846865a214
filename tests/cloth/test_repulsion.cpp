// Self-repulsion: the barrier kernel and the whole term against finite differences, exact zeros
// outside the range, the spatial hash against brute force, the excluded adjacent pairs, rigid
// motions, the objective with repulsion (gradient, Hessian pattern changes) and Newton on it.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <set>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/cloth/spatial_hash.hpp>
#include <fnopt/metrics/self_contact.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

constexpr double kDelta = 0.1;
const RepulsionKernel kKernel{2.5, kDelta};

// A pair at distance d in a random direction around a random point.
RepulsionKernel::Vec pair_at(double d, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Vec3 a(normal(rng), normal(rng), normal(rng));
  const Vec3 n = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
  RepulsionKernel::Vec x;
  x << a, a + d * n;
  return x;
}

TEST(RepulsionKernel, DerivativesMatchFiniteDifferencesInsideTheRange) {
  std::mt19937 rng(3);
  for (double s : {0.05, 0.2, 0.5, 0.8, 0.97}) {
    const RepulsionKernel::Vec x = pair_at(s * kDelta, rng);
    RepulsionKernel::Vec g;
    const double value = kKernel.gradient(x, g);
    EXPECT_NEAR(value, kKernel.energy(x), 1e-15);
    ASSERT_GT(value, 0.0);
    ASSERT_GT(g.norm(), 0.0) << "s = " << s;
    RepulsionKernel::Mat H, P;
    kKernel.hessian(x, H, false);
    kKernel.hessian(x, P, true);
    const double eps = 1e-7 * kDelta;
    const RepulsionKernel::Vec g_fd =
        testing::central_gradient([](const RepulsionKernel::Vec& y) { return kKernel.energy(y); }, x, eps);
    const RepulsionKernel::Mat H_fd = testing::central_jacobian(
        [](const RepulsionKernel::Vec& y) {
          RepulsionKernel::Vec gy;
          kKernel.gradient(y, gy);
          return Eigen::VectorXd(gy);
        },
        x, eps);
    EXPECT_LT((g - g_fd).norm(), 1e-6 * g.norm()) << "s = " << s;
    EXPECT_LT((H - H_fd).norm(), 1e-5 * H.norm()) << "s = " << s;
    EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
    // Inside the range the unprojected Hessian has a negative transverse eigenvalue; the
    // projection flips it.
    EXPECT_LT(Eigen::SelfAdjointEigenSolver<RepulsionKernel::Mat>(H).eigenvalues().minCoeff(), 0.0);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<RepulsionKernel::Mat>(P).eigenvalues().minCoeff(), -1e-12 * P.norm());
  }
}

TEST(RepulsionKernel, ExactlyZeroAtAndBeyondTheRange) {
  std::mt19937 rng(5);
  for (double s : {1.0, 1.0 + 1e-12, 1.3, 10.0}) {
    const RepulsionKernel::Vec x = pair_at(s * kDelta, rng);
    if ((x.tail<3>() - x.head<3>()).norm() < kDelta) continue;  // rounding put it inside
    RepulsionKernel::Vec g;
    g.setOnes();
    RepulsionKernel::Mat H;
    H.setOnes();
    EXPECT_EQ(kKernel.energy(x), 0.0);
    EXPECT_EQ(kKernel.gradient(x, g), 0.0);
    EXPECT_TRUE(g.isZero(0.0));
    kKernel.hessian(x, H, false);
    EXPECT_TRUE(H.isZero(0.0));
  }
  EXPECT_EQ(kKernel.barrier(kDelta), 0.0);
  EXPECT_EQ(kKernel.barrier(2 * kDelta), 0.0);
}

TEST(RepulsionKernel, IsTwiceContinuousAtTheRangeAndBlowsUpAtZero) {
  // b, b' and b'' tend to 0 as d -> delta from inside: the Hessian is continuous there.
  const double d = kDelta * (1.0 - 1e-6);
  EXPECT_LT(kKernel.barrier(d), 1e-12 * kKernel.stiffness * kDelta * kDelta);
  EXPECT_LT(std::abs(kKernel.barrier_derivative(d)), 1e-10 * kKernel.stiffness * kDelta);
  EXPECT_LT(std::abs(kKernel.barrier_second_derivative(d)), 1e-5 * kKernel.stiffness);
  EXPECT_GT(kKernel.barrier_second_derivative(0.5 * kDelta), 0.0);
  EXPECT_LT(kKernel.barrier_derivative(0.5 * kDelta), 0.0);  // repulsive
  EXPECT_GT(kKernel.barrier(1e-9 * kDelta), kKernel.barrier(0.5 * kDelta));
  EXPECT_TRUE(std::isinf(kKernel.barrier(0.0)));
}

std::set<std::pair<int, int>> brute_force_pairs(const VecX& x, double radius) {
  std::set<std::pair<int, int>> pairs;
  const int n = static_cast<int>(x.size() / 3);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((x.segment<3>(3 * i) - x.segment<3>(3 * j)).norm() < radius) pairs.insert({i, j});
  return pairs;
}

TEST(SpatialHash, FindsExactlyTheBruteForcePairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  SpatialHash hash;  // reused across sizes: stale buffers must not leak into a later build
  for (int n : {50, 400, 900}) {
    VecX x(3 * n);
    for (int i = 0; i < x.size(); ++i) x[i] = uniform(rng);
    for (double cell : {0.02, 0.07, 0.15, 0.4}) {
      hash.build(x, cell);
      for (double radius : {cell, 0.6 * cell}) {
        std::vector<SpatialHash::Pair> found;
        hash.pairs_within(x, radius, found);
        std::set<std::pair<int, int>> got;
        for (std::size_t k = 0; k < found.size(); ++k) {
          const auto& p = found[k];
          EXPECT_LT(p.i, p.j);
          EXPECT_NEAR(p.distance, (x.segment<3>(3 * p.i) - x.segment<3>(3 * p.j)).norm(), 1e-15);
          EXPECT_TRUE(got.insert({p.i, p.j}).second) << "pair reported twice";
          if (k > 0) {
            EXPECT_TRUE(std::make_pair(found[k - 1].i, found[k - 1].j) < std::make_pair(p.i, p.j));
          }
        }
        EXPECT_EQ(got, brute_force_pairs(x, radius)) << "n " << n << " cell " << cell << " radius " << radius;
      }
    }
  }
}

// A grid shrunk to `scale` of its rest size and jittered: many pairs within delta = h.
VecX crumpled(const Grid& grid, double scale, double jitter, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, jitter * grid.spacing);
  VecX x = scale * grid.rest_positions();
  for (int i = 0; i < x.size(); ++i) x[i] += normal(rng);
  return x;
}

RepulsionParams params_for(const Grid& grid) {
  RepulsionParams p;
  p.stiffness = 3.0;
  p.range = grid.spacing;
  return p;
}

TEST(RepulsionTerm, ExcludesAdjacentPairsAndKeepsEveryOtherPairInRange) {
  const Grid grid = Grid::make(7, 6, 0.5);
  std::mt19937 rng(9);
  const VecX x = crumpled(grid, 0.35, 0.1, rng);
  RepulsionTerm term(grid, params_for(grid));
  term.begin_step(x, x);
  std::set<std::pair<int, int>> candidates;
  for (const auto& p : term.candidates()) {
    EXPECT_FALSE(RepulsionTerm::adjacent(grid, p[0], p[1])) << p[0] << " " << p[1];
    candidates.insert({p[0], p[1]});
  }
  int in_range = 0, adjacent_in_range = 0;
  for (const auto& p : brute_force_pairs(x, grid.spacing)) {
    if (RepulsionTerm::adjacent(grid, p.first, p.second)) {
      ++adjacent_in_range;
      continue;
    }
    ++in_range;
    EXPECT_TRUE(candidates.count(p)) << p.first << " " << p.second;
  }
  ASSERT_GT(in_range, 20);
  ASSERT_GT(adjacent_in_range, 20);  // the exclusion was exercised
  // The exclusion is the 3x3 block around a vertex: edges and quad diagonals, nothing more.
  EXPECT_TRUE(RepulsionTerm::adjacent(grid, grid.index(2, 2), grid.index(3, 3)));
  EXPECT_TRUE(RepulsionTerm::adjacent(grid, grid.index(2, 2), grid.index(1, 3)));
  EXPECT_FALSE(RepulsionTerm::adjacent(grid, grid.index(2, 2), grid.index(2, 4)));
  EXPECT_FALSE(RepulsionTerm::adjacent(grid, grid.index(0, 5), grid.index(1, 0)));  // row wrap
}

TEST(RepulsionTerm, GradientAndHessianMatchFiniteDifferences) {
  const Grid grid = Grid::make(6, 5, 0.4);
  std::mt19937 rng(13);
  const VecX x = crumpled(grid, 0.4, 0.15, rng);
  RepulsionTerm term(grid, params_for(grid));
  term.begin_step(x, x);
  VecX g = VecX::Zero(x.size());
  const double value = term.accumulate_gradient(x, g);
  EXPECT_NEAR(value, term.energy(x), 1e-14 * value);
  ASSERT_GT(value, 0.0);
  ASSERT_GT(g.norm(), 0.0);
  const double eps = 1e-7 * grid.spacing;
  const VecX g_fd = testing::central_gradient([&](const VecX& y) { return term.energy(y); }, x, eps);
  for (int i = 0; i < x.size(); ++i) EXPECT_NEAR(g[i], g_fd[i], 1e-6 * g.norm()) << "dof " << i;
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const VecX& y) {
        VecX gy = VecX::Zero(y.size());
        term.accumulate_gradient(y, gy);
        return gy;
      },
      x, eps);
  std::vector<int> all_free(grid.vertex_count());
  for (int v = 0; v < grid.vertex_count(); ++v) all_free[v] = v;
  HessianAssembly assembly(all_free);
  const int handle = term.register_hessian(assembly);
  assembly.finalize();
  assembly.set_zero();
  term.accumulate_hessian(x, false, assembly, handle);
  const Eigen::MatrixXd H(assembly.matrix());
  EXPECT_LT((H - H_fd).norm(), 1e-5 * H.norm());
  assembly.set_zero();
  term.accumulate_hessian(x, true, assembly, handle);
  const Eigen::MatrixXd P(assembly.matrix());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues().minCoeff(), -1e-10 * P.norm());
}

TEST(RepulsionTerm, ZeroWhenNoPairIsInRange) {
  const Grid grid = Grid::make(8, 8, 1.0);
  const VecX x = grid.rest_positions();  // second neighbours at 2h: outside delta = h
  RepulsionTerm term(grid, params_for(grid));
  term.begin_step(x, x);
  EXPECT_TRUE(term.candidates().empty());
  VecX g = VecX::Zero(x.size());
  EXPECT_EQ(term.accumulate_gradient(x, g), 0.0);
  EXPECT_TRUE(g.isZero(0.0));
  EXPECT_EQ(term.energy(1.2 * x), 0.0);
}

TEST(RepulsionTerm, InvariantUnderRigidMotions) {
  const Grid grid = Grid::make(6, 6, 0.5);
  std::mt19937 rng(17);
  const VecX x = crumpled(grid, 0.4, 0.1, rng);
  RepulsionTerm term(grid, params_for(grid));
  term.begin_step(x, x);
  const double value = term.energy(x);
  ASSERT_GT(value, 0.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Vec3 t(3.0, -1.0, 0.25);
  VecX y(x.size());
  for (int k = 0; k < grid.vertex_count(); ++k) y.segment<3>(3 * k) = R * x.segment<3>(3 * k) + t;
  term.begin_step(y, y);
  EXPECT_NEAR(term.energy(y), value, 1e-12 * value);
  VecX g = VecX::Zero(y.size());
  term.accumulate_gradient(y, g);
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  for (int k = 0; k < grid.vertex_count(); ++k) {
    force += g.segment<3>(3 * k);
    torque += y.segment<3>(3 * k).cross(g.segment<3>(3 * k));
  }
  EXPECT_LT(force.norm(), 1e-10 * g.norm());
  EXPECT_LT(torque.norm(), 1e-9 * g.norm());
}

TEST(RepulsionTerm, CandidatesComeFromTheStartOrThePredictionAndThePatternOnlyGrows) {
  const Grid grid = Grid::make(5, 5, 1.0);
  RepulsionTerm term(grid, params_for(grid));
  const double h = grid.spacing;
  const RepulsionTerm::Pair pair{grid.index(0, 0), grid.index(3, 3)};
  const VecX far = grid.rest_positions();
  VecX near = far;
  near.segment<3>(3 * pair[0]) = vertex(far, pair[1]) + Vec3(0, 0.5 * h, 0);
  auto has_pair = [&] { return std::binary_search(term.candidates().begin(), term.candidates().end(), pair); };
  term.begin_step(far, far);
  EXPECT_TRUE(term.candidates().empty());
  const long generation = term.pattern_generation();
  term.begin_step(far, near);  // close only in the prediction: still a candidate
  EXPECT_TRUE(has_pair());
  for (const auto& p : term.candidates()) EXPECT_EQ(p[0], pair[0]);  // only the moved vertex
  EXPECT_EQ(term.pattern_generation(), generation + 1);
  term.begin_step(near, near);  // the same pairs: the pattern is kept
  EXPECT_TRUE(has_pair());
  EXPECT_EQ(term.pattern_generation(), generation + 1);
  term.begin_step(far, far);  // no candidates: a subset of the pattern, kept
  EXPECT_TRUE(term.candidates().empty());
  EXPECT_EQ(term.pattern_generation(), generation + 1);
  // The pair within delta at this step's start was not a candidate of the step before.
  term.begin_step(near, near);
  EXPECT_EQ(term.last_missed_pairs(), 1);
  EXPECT_EQ(term.pattern_generation(), generation + 1);
}

// A 10x10 cloth folded in half: rows 5-9 lie 0.6 h in front of rows 4-0.
VecX folded(const Grid& grid, double gap) {
  VecX x(grid.dof_count());
  const int R = grid.rows;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < grid.cols; ++j) {
      const bool back = i >= R / 2;
      x.segment<3>(3 * grid.index(i, j)) =
          Vec3(j * grid.spacing, back ? gap : 0.0, -(back ? (R - 1 - i) : i) * grid.spacing);
    }
  return x;
}

Material repulsive_material() {
  Material m;
  m.repulsion = true;
  return m;
}

TEST(ClothTerms, RepulsionIsBuiltOnlyWhenEnabled) {
  const Grid grid = Grid::make(4, 4, 1.0);
  for (const auto& term : make_cloth_terms(grid, Material{})) EXPECT_NE(term->name(), "repulsion");
  const auto terms = make_cloth_terms(grid, repulsive_material());
  ASSERT_EQ(terms.back()->name(), "repulsion");
  BackwardEulerObjective plain(grid, Material{}, 1.0 / 60.0, Vec3::Zero());
  EXPECT_EQ(plain.repulsion(), nullptr);
}

TEST(BackwardEulerObjective, GradientWithRepulsionMatchesFiniteDifferences) {
  const Grid grid = Grid::make(8, 6, 0.5);
  BackwardEulerObjective objective(grid, repulsive_material(), 1.0 / 60.0, Vec3(0, 0, -9.81));
  std::mt19937 rng(19);
  std::normal_distribution<double> normal(0.0, 1.0);
  const VecX x = folded(grid, 0.6 * grid.spacing);
  VecX v(grid.dof_count()), a(grid.dof_count());
  for (int i = 0; i < v.size(); ++i) {
    v[i] = 0.05 * normal(rng);
    a[i] = 2.0 * normal(rng);
  }
  objective.begin_step(x, v);
  ASSERT_NE(objective.repulsion(), nullptr);
  ASSERT_GT(objective.repulsion()->candidates().size(), 5u);
  VecX xa;
  objective.trial_positions(a, xa);
  VecX g_rep = VecX::Zero(xa.size());
  ASSERT_GT(objective.repulsion()->accumulate_gradient(xa, g_rep), 0.0);
  ASSERT_GT(g_rep.norm(), 0.0);
  VecX g;
  objective.value_gradient(a, g);
  const double eps = 1e-3;
  const VecX g_fd = testing::central_gradient([&](const VecX& y) { return objective.value(y); }, a, eps);
  for (int i = 0; i < a.size(); ++i) EXPECT_NEAR(g[i], g_fd[i], 1e-6 * g.norm()) << "dof " << i;
  // And the Hessian against differences of the gradient.
  std::vector<int> all_free(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) all_free[k] = k;
  const Eigen::MatrixXd H(objective.hessian(a, all_free, false));
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const VecX& y) {
        VecX gy;
        objective.value_gradient(y, gy);
        return gy;
      },
      a, eps);
  EXPECT_LT((H - H_fd).norm(), 1e-6 * H.norm());
}

// Newton keys its symbolic analysis on hessian_pattern_id(): every new pattern needs a new id,
// also across objectives, and an unchanged pattern keeps its id.
TEST(BackwardEulerObjective, EveryRepulsionPatternGetsItsOwnId) {
  const Grid grid = Grid::make(6, 6, 1.0);
  BackwardEulerObjective objective(grid, repulsive_material(), 1.0 / 60.0, Vec3::Zero());
  BackwardEulerObjective other(grid, repulsive_material(), 1.0 / 60.0, Vec3::Zero());
  std::vector<int> all_free(grid.vertex_count());
  for (int k = 0; k < grid.vertex_count(); ++k) all_free[k] = k;
  const VecX zero = VecX::Zero(grid.dof_count());
  std::set<long> ids;
  std::mt19937 rng(23);
  int changes = 0;
  long id = -1;
  for (int step = 0; step < 12; ++step) {
    // Alternate flat and crumpled states: the pattern changes whenever new pairs appear.
    const VecX x = step % 2 ? crumpled(grid, 0.4, 0.2, rng) : grid.rest_positions();
    objective.begin_step(x, zero);
    const long nnz = objective.hessian(zero, all_free, true).nonZeros();
    if (objective.hessian_pattern_id() != id) {
      ++changes;
      EXPECT_TRUE(ids.insert(objective.hessian_pattern_id()).second) << "a pattern id was reused";
      id = objective.hessian_pattern_id();
    }
    objective.hessian(zero, all_free, false);
    EXPECT_EQ(objective.hessian_pattern_id(), id) << "the same pattern must keep its id";
    EXPECT_EQ(objective.hessian(zero, all_free, true).nonZeros(), nnz);
  }
  EXPECT_GE(changes, 3);
  other.begin_step(grid.rest_positions(), zero);
  other.hessian(zero, all_free, true);
  EXPECT_FALSE(ids.count(other.hessian_pattern_id())) << "another objective's pattern reused an id";
}

TEST(NewtonWithRepulsion, ConvergesOnAFoldedClothAcrossPatternChanges) {
  const Grid grid = Grid::make(10, 10, 0.5);
  BackwardEulerObjective objective(grid, repulsive_material(), 1.0 / 60.0, Vec3(0, 0, -9.81));
  const int left = grid.index(0, 0), right = grid.index(0, grid.cols - 1);
  const DirichletSet handles(grid.vertex_count(), {left, right});
  StepProblem problem(objective, handles);
  NewtonOptimizer newton;  // factors reused across steps: it must notice the new pattern
  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count());
  SpatialHash hash;
  long generation_before_fold = 0;
  for (int step = 0; step < 18; ++step) {
    if (step == 3) {  // jump to a folded cloth whose back half moves towards the front
      generation_before_fold = objective.repulsion()->pattern_generation();
      x = folded(grid, 0.6 * grid.spacing);
      v.setZero();
      for (int k = grid.vertex_count() / 2; k < grid.vertex_count(); ++k) v[3 * k + 1] = -0.5;
    }
    const long pattern = objective.hessian_pattern_id();
    objective.begin_step(x, v);
    VecX a = VecX::Zero(grid.dof_count());
    handles.prescribe(a, x, v, {vertex(x, left), vertex(x, right)}, 1.0 / 60.0);
    const InnerSolveResult result = solve_step(newton, problem, a, NewtonOptimizer::reference_solve_options());
    ASSERT_EQ(result.status, SolveStatus::Converged) << "step " << step;
    if (step == 3) {
      EXPECT_GT(objective.hessian_pattern_id(), pattern);
    }
    v += a / 60.0;
    x += v / 60.0;
    ASSERT_TRUE(x.allFinite());
    // The barrier keeps the halves apart: no pair closer than a quarter of delta.
    EXPECT_EQ(measure_self_contact(grid, x, hash).pairs_quarter, 0) << "step " << step;
  }
  EXPECT_GT(objective.repulsion()->pattern_generation(), generation_before_fold);
}

TEST(SelfContactMetric, CountsPairsAndSummarises) {
  const Grid grid = Grid::make(10, 10, 0.5);
  SpatialHash hash;
  const SelfContactFrame flat = measure_self_contact(grid, grid.rest_positions(), hash);
  EXPECT_EQ(flat.pairs_within, 0);
  EXPECT_EQ(flat.energy, 0.0);
  EXPECT_EQ(flat.min_distance, 1.0);
  const SelfContactFrame fold = measure_self_contact(grid, folded(grid, 0.2 * grid.spacing), hash);
  // Back row i faces front row 9 - i at 0.2 h; rows 5 and 4 share edges (excluded), so rows
  // 6..9 against 3..0: 4 rows x 10 columns, each straight across.
  EXPECT_EQ(fold.pairs_within, 40);
  EXPECT_EQ(fold.pairs_quarter, 40);
  EXPECT_NEAR(fold.min_distance, 0.2, 1e-12);
  const RepulsionKernel reference{kSelfContactReferenceStiffness, grid.spacing};
  EXPECT_NEAR(fold.energy, 40 * reference.barrier(0.2 * grid.spacing), 1e-12 * fold.energy);
  const SelfContactSummary s = summarize_self_contact({flat, fold, fold, flat});
  EXPECT_EQ(s.frames, 4);
  EXPECT_NEAR(s.mean_energy, fold.energy / 2, 1e-15);
  EXPECT_EQ(s.max_pairs_quarter, 40);
  EXPECT_DOUBLE_EQ(s.frames_with_quarter, 0.5);
}

}  // namespace
}  // namespace fnopt
