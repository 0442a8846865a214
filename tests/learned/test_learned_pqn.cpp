// pqn with the learned optimizer's proposals (fnopt-pqn): the schedule, one-line errors for bad
// parameters, handles that never move and an energy that never rises on the step's grid and
// on a coarser one, and agreement with a naive reference of one proposal and the pqn
// iteration after it. (Whether it pays is `compare`'s to say: docs/design.md §13.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_pqn.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/util/error.hpp>
#include "tests/learned/step_probes.hpp"
#include "tests/util/cloth_step.hpp"

namespace fnopt {
namespace {

FNO2d tiny_model() {
  torch::manual_seed(5);
  return FNO2d(
      FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4));
}

LearnedPqnParams schedule(int coarse_size, int first, int every) {
  LearnedPqnParams params;
  params.coarse_size = coarse_size;
  params.first = first;
  params.every = every;
  return params;
}

TEST(LearnedPqn, ProposesAtTheIterationsOfItsSchedule) {
  std::vector<int> once, every_three;
  for (int k = 0; k < 10; ++k) {
    if (schedule(32, 1, 0).proposes_at(k)) once.push_back(k);
    if (schedule(32, 2, 3).proposes_at(k)) every_three.push_back(k);
  }
  EXPECT_EQ(once, (std::vector<int>{1}));
  EXPECT_EQ(every_three, (std::vector<int>{2, 5, 8}));
}

TEST(LearnedPqn, BadParametersAreOneLineErrors) {
  for (auto [params, field] :
       {std::pair{schedule(2, 0, 0), "fnopt-pqn.coarse_size"}, std::pair{schedule(32, -1, 0), "fnopt-pqn.first"},
        std::pair{schedule(32, 0, -2), "fnopt-pqn.every"}}) {
    try {
      LearnedPqnOptimizer optimizer(tiny_model(), "tiny", params);
      ADD_FAILURE() << field << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(LearnedPqnOptimizer("/nonexistent/model.pt"), Error);
}

TEST(LearnedPqn, NeverMovesAHandleNorRaisesTheEnergyOnTheStepsGridOrACoarserOne) {
  // An untrained model proposes poor directions: their pairs inform pqn, whose line search
  // still only goes downhill.
  for (int coarse_size : {0, 8}) {
    ClothStep step;
    LearnedPqnOptimizer optimizer(tiny_model(), "tiny", schedule(coarse_size, 0, 2));
    EnergyLog log(optimizer);
    const InnerSolveResult result = solve_step(log, step.problem, step.a, {10, 0.0});
    EXPECT_EQ(result.iterations, 10);
    EXPECT_EQ(optimizer.proposals(), 5) << "proposals at iterations 0, 2, 4, 6, 8";
    EXPECT_LE(optimizer.kept_pairs(), optimizer.proposals());
    for (std::size_t k = 1; k < log.values.size(); ++k) EXPECT_LE(log.values[k], log.values[k - 1]) << k;
    EXPECT_LT(log.values.back(), log.values.front());
    ClothStep start;
    for (int h : step.handles.fixed_vertices())
      EXPECT_EQ(step.a.segment<3>(3 * h), start.a.segment<3>(3 * h)) << "coarse " << coarse_size << " handle " << h;
  }
}

TEST(LearnedPqn, AStepInTheClothsPlaneStaysInIt) {
  // The rest pose lies in the plane y = 0 (cloth/grid.hpp); under gravity and a velocity in
  // that plane every force is in it, g_y = 0, and the exact step has a_y = 0. The FNO
  // normalises each coordinate alone, so its y proposal is made of nothing; left in, its pair
  // would turn pqn out of the plane. The gate leaves it out.
  const Grid grid = Grid::make(12, 12, 1.0);
  BackwardEulerObjective objective(grid, Material{}, 1.0 / 60.0, Vec3(0, 0, -9.81));
  const DirichletSet handles(grid.vertex_count(), {0, 11});
  StepProblem problem(objective, handles);
  VecX v = VecX::Zero(grid.dof_count());
  for (int k = 0; k < grid.vertex_count(); ++k) v[3 * k] = 0.5 * (k / grid.cols) / grid.rows;
  objective.begin_step(grid.rest_positions(), v);
  VecX a = VecX::Zero(grid.dof_count());
  LearnedPqnOptimizer optimizer(tiny_model(), "tiny", schedule(0, 0, 2));
  solve_step(optimizer, problem, a, {6, 0.0});
  ASSERT_EQ(optimizer.proposals(), 3);
  double in_plane = 0.0, out_of_plane = 0.0;
  for (int k = 0; k < grid.vertex_count(); ++k) {
    in_plane = std::max({in_plane, std::abs(a[3 * k]), std::abs(a[3 * k + 2])});
    out_of_plane = std::max(out_of_plane, std::abs(a[3 * k + 1]));
  }
  EXPECT_GT(in_plane, 0.0);
  EXPECT_EQ(out_of_plane, 0.0);
}

TEST(LearnedPqn, AgreesWithANaiveReferenceOfAProposalAndThePqnIterationAfterIt) {
  // Built from the public pieces on the step's own grid: p = the FNO's update from g at a fresh
  // state (handles masked, turned downhill), alpha = -g.p / p^T A p, the trial's pair given to
  // a fresh pqn, then one pqn iteration from a. fnopt-pqn's first iteration must land on the
  // same a, and differ from pqn's own first iteration (-A^-1 g). Every coordinate has a
  // gradient in this step, so the coordinate gate leaves p as it is.
  FNO2d model = tiny_model();
  LearnedPqnOptimizer hybrid(model, "tiny", schedule(0, 0, 0));
  ClothStep step;
  solve_step(hybrid, step.problem, step.a, {1, 0.0});
  ASSERT_EQ(hybrid.proposals(), 1);
  ASSERT_EQ(hybrid.kept_pairs(), 1);

  torch::NoGradGuard no_grad;
  ClothStep naive;
  VecX a = naive.a, g;
  double value = naive.problem.value_gradient(a, g);
  const LearnedStep proposal =
      learned_step(model, to_coordinate_samples(g, naive.grid), LearnedState{}, free_mask(naive.handles, naive.grid));
  VecX p = VecX::Zero(a.size());
  add_coordinate_samples(proposal.delta, naive.grid, 1.0, p);
  naive.handles.zero_fixed(p);
  if (g.dot(p) > 0.0) p = -p;
  PqnOptimizer pqn;
  pqn.begin_step(naive.problem, a, value, g);
  VecX trial = a - g.dot(p) / pqn.factor().quadratic_form(p) * p, trial_gradient;
  naive.problem.value_gradient(trial, trial_gradient);
  ASSERT_TRUE(pqn.add_pair(a, g, trial, trial_gradient));
  pqn.iterate(naive.problem, a, value, g);
  EXPECT_LT((a - step.a).norm(), 1e-12 * a.norm());

  ClothStep plain, start;
  PqnOptimizer pqn_alone;
  solve_step(pqn_alone, plain.problem, plain.a, {1, 0.0});
  EXPECT_GT((plain.a - step.a).norm(), 1e-3 * (plain.a - start.a).norm()) << "the pair changed nothing";
}

}  // namespace
}  // namespace fnopt
