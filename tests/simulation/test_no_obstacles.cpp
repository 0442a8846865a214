// Contact costs nothing without obstacles: no contact term is built, and a 32x32 xy_v2 rollout with
// Newton and with pqn gives bit for bit the positions of the loop written without contact (the
// objective's original constructor, begin_step without a time, no feasibility filter calls).
#include <gtest/gtest.h>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/simulation/simulator.hpp>

namespace fnopt {
namespace {

// The rollout loop as it was before obstacles existed.
std::vector<VecX> plain_loop(const ResolvedScene& setup, InnerOptimizer& optimizer, const InnerSolveOptions& solve) {
  const Scene& scene = setup.scene;
  BackwardEulerObjective objective(setup.grid, scene.material, scene.dt, scene.gravity);
  DirichletSet dirichlet(setup.grid.vertex_count(), setup.handles.vertices);
  StepProblem problem(objective, dirichlet);
  VecX x = setup.grid.rest_positions(), v = VecX::Zero(x.size()), a = VecX::Zero(x.size());
  std::vector<VecX> frames = {x};
  for (int step = 0; step < scene.frames; ++step) {
    std::vector<Vec3> targets;
    for (std::size_t h = 0; h < setup.handles.vertices.size(); ++h)
      targets.push_back(setup.trajectory->position(static_cast<int>(h), (step + 1) * scene.dt));
    objective.begin_step(x, v);
    a.setZero();
    dirichlet.prescribe(a, x, v, targets, scene.dt);
    solve_step(optimizer, problem, a, solve);
    v += scene.dt * a;
    x += scene.dt * v;
    frames.push_back(x);
  }
  return frames;
}

TEST(NoObstacles, NoContactTermIsBuilt) {
  const ResolvedScene setup = resolve(Scene{});
  BackwardEulerObjective with_empty_list(setup.grid, setup.scene.material, setup.scene.dt, setup.scene.gravity, {});
  BackwardEulerObjective plain(setup.grid, setup.scene.material, setup.scene.dt, setup.scene.gravity);
  EXPECT_EQ(with_empty_list.contact(), nullptr);
  EXPECT_EQ(with_empty_list.terms().size(), plain.terms().size());
  DirichletSet dirichlet(setup.grid.vertex_count(), setup.handles.vertices);
  StepProblem problem(with_empty_list, dirichlet);
  EXPECT_FALSE(problem.has_contact());
  const VecX a = VecX::Random(setup.grid.dof_count());
  EXPECT_EQ(problem.feasible_fraction(a, -a), 1.0);
  EXPECT_EQ(problem.feasible_step(a, a, 0.75), 0.75);
  VecX start = a;
  problem.make_start_feasible(start);
  EXPECT_EQ(start, a);
}

TEST(NoObstacles, RolloutsAreBitForBitThoseOfTheLoopWithoutContact) {
  Scene scene;
  scene.frames = 6;
  const ResolvedScene setup = resolve(scene);
  auto check = [&](InnerOptimizer& first, InnerOptimizer& second, const InnerSolveOptions& solve) {
    RolloutOptions options;
    options.solve = solve;
    Simulator simulator(setup, first, options);
    const std::vector<VecX> expected = plain_loop(setup, second, solve);
    EXPECT_EQ(simulator.positions(), expected[0]);
    for (std::size_t f = 1; f < expected.size(); ++f) {
      simulator.step();
      EXPECT_EQ(simulator.positions(), expected[f]) << first.name() << " frame " << f;
    }
  };
  NewtonOptimizer newton_a, newton_b;
  check(newton_a, newton_b, NewtonOptimizer::reference_solve_options());
  PqnOptimizer pqn_a, pqn_b;
  check(pqn_a, pqn_b, {20});
}

}  // namespace
}  // namespace fnopt
