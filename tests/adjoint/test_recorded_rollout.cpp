// The recorded forward pass: every step at a stationary point of its energy, the states obeying
// the step's update exactly, handles at their targets, another optimizer's steps polished onto the
// same stationary points as Newton's, and its inputs checked.
#include <gtest/gtest.h>

#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

ResolvedScene small_scene() {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 31;
  scene.speed = 4.0;
  return resolve(scene);
}

TEST(RecordedRollout, EveryStepIsAStationaryPointAndTheStatesFollowTheUpdate) {
  const ResolvedScene scene = small_scene();
  const RecordedRollout rollout = record_rollout(scene);
  ASSERT_EQ(rollout.frame_count(), scene.scene.frames);
  ASSERT_EQ(rollout.step_count(), scene.scene.frames - 1);
  EXPECT_EQ(rollout.unconverged_steps(), 0);
  EXPECT_EQ(rollout.polished_steps(), 0);
  const double dt = scene.scene.dt;
  for (int s = 0; s < rollout.step_count(); ++s) {
    EXPECT_LE(rollout.steps[s].residual_acceleration, 1e-9) << s;
    EXPECT_TRUE(rollout.steps[s].stationarity.has_value());
    const VecX& a = rollout.accelerations[s];
    EXPECT_LE((rollout.velocities[s + 1] - rollout.velocities[s] - dt * a).norm(), 1e-12) << s;
    EXPECT_LE((rollout.positions[s + 1] - rollout.positions[s] - dt * rollout.velocities[s + 1]).norm(), 1e-12) << s;
    for (std::size_t h = 0; h < scene.handles.vertices.size(); ++h)
      EXPECT_LE(
          (rollout.positions[s + 1].segment<3>(3 * scene.handles.vertices[h]) - rollout.handle_targets[s][h]).norm(),
          1e-12);
  }
}

TEST(RecordedRollout, AnotherOptimizerPolishedByNewtonEndsOnNewtonsStationaryPoints) {
  const ResolvedScene scene = small_scene();
  const RecordedRollout newton = record_rollout(scene);
  PqnOptimizer pqn;
  const RecordedRollout polished = record_rollout(scene, pqn, {5, 0.0});
  EXPECT_EQ(polished.polished_steps(), polished.step_count());
  EXPECT_EQ(polished.unconverged_steps(), 0);
  for (int f = 0; f < newton.frame_count(); ++f)
    EXPECT_LE((polished.positions[f] - newton.positions[f]).norm(), 1e-9) << f;
}

TEST(RecordedRollout, TheGivenInitialStateAndTargetsAreUsedAndTheMemoryCounted) {
  const ResolvedScene scene = small_scene();
  RolloutInputs inputs;
  inputs.initial_velocities = VecX::Constant(scene.grid.dof_count(), 0.1);
  inputs.handle_targets = std::vector<std::vector<Vec3>>(scene.scene.frames - 1);
  for (auto& targets : *inputs.handle_targets)
    for (int k : scene.handles.vertices) targets.push_back(scene.grid.rest_positions().segment<3>(3 * k));
  const RecordedRollout rollout = record_rollout(scene, {}, inputs);
  EXPECT_EQ(rollout.velocities.front(), *inputs.initial_velocities);
  EXPECT_EQ(rollout.handle_targets, *inputs.handle_targets);
  const std::size_t dofs = scene.grid.dof_count();
  const std::size_t frames = rollout.frame_count();
  EXPECT_EQ(rollout.memory_bytes(),
            (2 * frames + (frames - 1)) * dofs * sizeof(double) + (frames - 1) * 2 * sizeof(Vec3));
}

TEST(RecordedRollout, InputsThatDoNotFitAreErrors) {
  const ResolvedScene scene = small_scene();
  RolloutInputs rows;
  rows.handle_targets = std::vector<std::vector<Vec3>>(3, std::vector<Vec3>(2, Vec3::Zero()));
  EXPECT_THROW(record_rollout(scene, {}, rows), Error);
  RolloutInputs starts;
  starts.start_accelerations = std::vector<VecX>(scene.scene.frames - 1, VecX::Zero(6));
  EXPECT_THROW(record_rollout(scene, {}, starts), Error);
  RolloutInputs state;
  state.initial_positions = VecX::Zero(5);
  EXPECT_THROW(record_rollout(scene, {}, state), Error);
  RecordOptions options;
  options.acceleration_tolerance = 0.0;
  EXPECT_THROW(record_rollout(scene, options), Error);
}

// A horizontal placement starts the record where the scene places the cloth, as a simulation does.
TEST(RecordedRollout, StartsWhereTheScenePlacesTheCloth) {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 3;
  scene.placement = Placement::Horizontal;
  const ResolvedScene resolved = resolve(scene);
  const RecordedRollout rollout = record_rollout(resolved);
  EXPECT_EQ(rollout.positions.front(), resolved.rest_positions);
  EXPECT_NE(rollout.positions.front(), resolved.grid.rest_positions());
}

// Handles let go mid-way: the steps that end after the let-go time are marked released, and from
// then on the handle vertices fall with the cloth instead of following the motion.
TEST(RecordedRollout, StepsAfterTheLetGoAreReleased) {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 11;
  scene.let_go = 4.5 * scene.dt;
  const ResolvedScene resolved = resolve(scene);
  const RecordedRollout rollout = record_rollout(resolved);
  ASSERT_EQ(rollout.step_count(), 10);
  for (int s = 0; s < rollout.step_count(); ++s) EXPECT_EQ(rollout.steps[s].released, s >= 4) << "step " << s;
  const int corner = resolved.handles.vertices.front();
  const double held_z = resolved.start_positions()[3 * corner + 2];
  EXPECT_NEAR(rollout.positions[4][3 * corner + 2], held_z, 1e-12);  // the motion starts at 0.5 s
  EXPECT_LT(rollout.positions[10][3 * corner + 2], held_z - 1e-3);
}

}  // namespace
}  // namespace fnopt
