// The simulator, a rollout one step at a time: driven along the scene's trajectory it is
// run_rollout bit for bit; handles given per step go exactly there; an acceleration of one's own
// is committed with the handles' prescription kept; a divergence stops it with its reason;
// obstacles steered step by step go where they are told, as a motion of theirs would.
#include <gtest/gtest.h>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/simulation/simulator.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

ResolvedScene small_scene(const std::string& motion = "xy_v2") {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 12;
  scene.motion = motion;
  return resolve(scene);
}

RolloutOptions pqn_options() {
  RolloutOptions options;
  options.solve = {10, 0.0};
  return options;
}

TEST(Simulator, SteppedAlongTheTrajectoryItIsTheRolloutBitForBit) {
  const ResolvedScene scene = small_scene();
  PqnOptimizer whole_pqn, stepped_pqn;
  const RolloutResult whole = run_rollout(scene, whole_pqn, pqn_options());
  Simulator simulator(scene, stepped_pqn, pqn_options());
  for (int t = 1; t <= scene.scene.frames; ++t) {
    const StepRecord record = simulator.step();
    EXPECT_EQ(record.iterations, whole.steps[t - 1].iterations);
    ASSERT_TRUE((simulator.positions().cast<float>().array() == whole.positions[t].array()).all()) << "frame " << t;
    EXPECT_EQ(simulator.time(), whole.times[t]);
  }
  EXPECT_EQ(simulator.steps_done(), scene.scene.frames);
}

TEST(Simulator, HandlesGivenPerStepGoExactlyThere) {
  const ResolvedScene scene = small_scene("static");
  PqnOptimizer pqn;
  Simulator simulator(scene, pqn, pqn_options());
  for (int t = 1; t <= 5; ++t) {
    std::vector<Vec3> handles;
    for (int v : simulator.handle_vertices()) handles.push_back(vertex(simulator.positions(), v) + Vec3(0.01, 0, 0.02));
    simulator.step(handles);
    for (std::size_t h = 0; h < handles.size(); ++h)
      EXPECT_LT((vertex(simulator.positions(), simulator.handle_vertices()[h]) - handles[h]).norm(), 1e-12);
  }
  EXPECT_THROW(simulator.step(std::vector<Vec3>(1)), Error);
  EXPECT_THROW(simulator.step(std::vector<Vec3>(2, Vec3(NAN, 0, 0))), Error);
}

TEST(Simulator, AnAccelerationOfOnesOwnKeepsTheHandlesPrescription) {
  const ResolvedScene scene = small_scene();
  PqnOptimizer pqn_a, pqn_b;
  Simulator built_in(scene, pqn_a, pqn_options()), own(scene, pqn_b, pqn_options());
  built_in.step();
  VecX start;
  StepProblem& problem = own.prepare_step(start);
  VecX a = start;
  solve_step(pqn_b, problem, a, pqn_options().solve);
  for (int v : own.handle_vertices()) a.segment<3>(3 * v).setConstant(1e6);  // ignored
  own.commit(a);
  EXPECT_TRUE((own.positions().array() == built_in.positions().array()).all());
}

TEST(Simulator, ADivergenceStopsItWithItsReasonAndAFiniteStateRestartsIt) {
  const ResolvedScene scene = small_scene();
  PqnOptimizer pqn;
  Simulator simulator(scene, pqn, pqn_options());
  VecX start;
  simulator.prepare_step(start);
  const VecX before = simulator.positions();
  simulator.commit(VecX::Constant(start.size(), 1e9));  // flung apart
  ASSERT_TRUE(simulator.diverged());
  EXPECT_NE(simulator.divergence().find("diverged at step 1"), std::string::npos) << simulator.divergence();
  EXPECT_TRUE((simulator.positions().array() == before.array()).all());  // the state before it
  EXPECT_THROW(simulator.step(), Error);
  EXPECT_THROW(simulator.set_state(before, VecX::Constant(before.size(), NAN)), Error);
  simulator.set_state(before, VecX::Zero(before.size()));
  simulator.step();
  EXPECT_FALSE(simulator.diverged());
  EXPECT_THROW(simulator.set_state(before, VecX::Zero(before.size()), -1), Error);
}

TEST(Simulator, AStateSetWithItsStepsContinuesTheRollout) {
  const ResolvedScene scene = small_scene();
  PqnOptimizer pqn_a, pqn_b;
  Simulator whole(scene, pqn_a, pqn_options()), resumed(scene, pqn_b, pqn_options());
  for (int t = 0; t < 5; ++t) whole.step();
  resumed.set_state(whole.positions(), whole.velocities(), 5);
  EXPECT_EQ(resumed.time(), whole.time());
  whole.step();
  resumed.step();  // the handles at step 6's targets, as in the whole rollout
  EXPECT_TRUE((resumed.positions().array() == whole.positions().array()).all());
}

// A sphere swept through the hanging cloth along xy_v2, out of the cloth's plane.
ResolvedScene pushed_scene() {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 60;
  scene.motion = "static";
  scene.obstacles = {parse_obstacle("sphere center=0,-0.3,-0.4 radius=0.15 motion=xy_v2")};
  return resolve(scene);
}

TEST(Simulator, ObstaclesSteeredAlongTheirMotionAreThatMotion) {
  const ResolvedScene scene = pushed_scene();
  PqnOptimizer moving_pqn, steered_pqn;
  Simulator moving(scene, moving_pqn, pqn_options()), steered(scene, steered_pqn, pqn_options());
  const Obstacle& sphere = scene.scene.obstacles[0];
  double largest_offset = 0.0;
  for (int t = 1; t <= scene.scene.frames; ++t) {
    moving.step();
    const Vec3 target = sphere.offset(steered.time() + scene.scene.dt);
    steered.set_obstacle_offsets({target});
    steered.step();
    ASSERT_EQ(steered.obstacle_offsets().size(), 1u);
    EXPECT_EQ(steered.obstacle_offsets()[0], target);
    EXPECT_LT((steered.positions() - moving.positions()).cwiseAbs().maxCoeff(), 1e-9) << "step " << t;
    largest_offset = std::max(largest_offset, steered.obstacle_offsets()[0].norm());
  }
  EXPECT_GT(largest_offset, 0.1);  // the sphere did move
}

TEST(Simulator, ASteeredObstacleGoesWhereItIsToldAndPushesTheCloth) {
  Scene still = pushed_scene().scene;
  still.obstacles = {parse_obstacle("sphere center=0,-0.3,-0.4 radius=0.15")};
  const ResolvedScene scene = resolve(still);
  PqnOptimizer pqn;
  Simulator simulator(scene, pqn, pqn_options());
  EXPECT_EQ(simulator.obstacle_offsets(), std::vector<Vec3>{Vec3::Zero()});
  double pushed = 0.0;
  for (int t = 1; t <= 40; ++t) {
    const Vec3 offset(0.0, 0.015 * t, 0.0);  // through the cloth's plane y = 0 and 0.3 m beyond
    simulator.set_obstacle_offsets({offset});
    simulator.step();
    EXPECT_EQ(simulator.obstacle_offsets()[0], offset);
    const Vec3 centre = Vec3(0.0, -0.3, -0.4) + offset;
    for (int v = 0; v < scene.grid.vertex_count(); ++v) {
      EXPECT_GE((vertex(simulator.positions(), v) - centre).norm(), 0.15) << "step " << t << " vertex " << v;
      pushed = std::max(pushed, vertex(simulator.positions(), v).y());
    }
  }
  EXPECT_GT(pushed, 0.1);
  EXPECT_THROW(simulator.set_obstacle_offsets({}), Error);
  EXPECT_THROW(simulator.set_obstacle_offsets({Vec3(NAN, 0, 0)}), Error);
  // A state set anew puts the obstacle back on its motion (here: still).
  simulator.set_state(simulator.positions(), simulator.velocities());
  EXPECT_EQ(simulator.obstacle_offsets(), std::vector<Vec3>{Vec3::Zero()});
}

// With self-contact, a state where the cloth is within its thickness of itself is refused with the
// pair named: here row 7 folded back onto row 3, 0.5 mm off.
TEST(Simulator, AStartWithinTheSelfContactThicknessIsRefusedNamingThePair) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 3;
  scene.self_contact = AutoSwitch::On;
  const ResolvedScene resolved = resolve(scene);
  PqnOptimizer pqn;
  Simulator simulator(resolved, pqn, {});
  VecX x = resolved.start_positions();
  const VecX v = VecX::Zero(x.size());
  simulator.set_state(x, v);  // flat: fine
  for (int j = 0; j < 8; ++j)
    x.segment<3>(3 * resolved.grid.index(7, j)) = x.segment<3>(3 * resolved.grid.index(3, j)) + Vec3(0, 5e-4, 0);
  try {
    simulator.set_state(x, v);
    FAIL() << "not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "state");
    EXPECT_NE(std::string(e.what()).find("within its self-contact thickness of itself"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(7,"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fnopt
