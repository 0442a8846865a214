// The adjoint against central differences of the rollout (adjoint/gradient_check.hpp), for every
// parameter kind, on scenes that exercise different parts of the step: handles moving fast along
// the scene's motion, handles given per step along a path of one's own, a cloth folding onto
// itself with self-repulsion acting, and steps that end at saddles.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/adjoint/gradient_check.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr double kTolerance = 1e-4;  // relative, per comparison

void expect_every_kind_within(const GradientCheckResult& result, std::size_t kinds) {
  ASSERT_EQ(result.rows.size(), kinds);
  for (const GradientCheckRow& row : result.rows) {
    EXPECT_LE(row.max_relative_error, kTolerance)
        << to_string(row.parameter) << ": adjoint " << row.adjoint_norm << ", differences "
        << row.finite_difference_norm << "; " << to_string(result.status) << ", " << result.saddle_steps
        << " saddle steps";
    EXPECT_GT(row.adjoint_norm, 0.0) << to_string(row.parameter);
  }
  EXPECT_TRUE(is_complete(result.status)) << to_string(result.status);
}

// 10 x 10 over 30 steps; xy_v2 four times faster, so that the handles move from frame 8 on.
ResolvedScene fast_corner_scene() {
  Scene scene;
  scene.rows = scene.cols = 10;
  scene.frames = 31;
  scene.speed = 4.0;
  return resolve(scene);
}

TEST(GradientCheck, EveryKindInLogCoordinatesWithFastHandles) {
  const ResolvedScene scene = fast_corner_scene();
  const GradientCheckResult result = gradient_check(scene);
  expect_every_kind_within(result, all_adjoint_parameters().size());
  EXPECT_LE(result.max_relative_error, kTolerance);
  for (const GradientCheckRow& row : result.rows) EXPECT_EQ(row.unreliable, "") << to_string(row.parameter);
}

// At 12² the cloth buckles within the 30 steps: along the start state, the differences run over
// orders of magnitude as the step shrinks. Every kind either agrees within the tolerance, its
// differences settled, or says why it is unreliable; the start positions say it. Without a sweep
// there is no settling to judge, and only the disagreement is reported.
TEST(GradientCheck, ABucklingClothSaysWhichKindsAreUnreliable) {
  Scene scene;
  scene.rows = scene.cols = 12;
  scene.frames = 31;
  scene.speed = 4.0;
  GradientCheckParams params;
  params.parameters = {AdjointParameter::Bend, AdjointParameter::Gravity, AdjointParameter::InitialPositions};
  const GradientCheckResult result = gradient_check(resolve(scene), params);
  ASSERT_EQ(result.rows.size(), 3u);
  for (const GradientCheckRow& row : result.rows) {
    if (row.unreliable.empty()) {
      EXPECT_LE(row.max_relative_error, kTolerance) << to_string(row.parameter);
    }
  }
  EXPECT_EQ(result.rows[0].unreliable, "");
  EXPECT_LE(result.rows[0].max_relative_error, kTolerance);
  EXPECT_EQ(result.rows[2].unreliable.rfind("central differences do not settle as the step shrinks (", 0), 0u)
      << result.rows[2].unreliable;
  params.sweep_decades = 0;
  params.parameters = {AdjointParameter::InitialPositions};
  const GradientCheckResult single = gradient_check(resolve(scene), params);
  EXPECT_EQ(single.rows[0].unreliable.rfind("the adjoint's ", 0), 0u) << single.rows[0].unreliable;
  EXPECT_EQ(single.rows[0].unreliable.find("settled"), std::string::npos) << single.rows[0].unreliable;
}

// The handles let go a third of the way in: every vertex free from then on, the handles' later
// targets without effect. The falling cloth is softer still out of its plane than the held one, so
// the initial positions' differences need a smaller step (their error falls with the step's square:
// truncation, not the adjoint; docs/design.md §15).
TEST(GradientCheck, EveryKindWithTheHandlesLetGo) {
  Scene scene;
  scene.rows = scene.cols = 10;
  scene.frames = 31;
  scene.speed = 4.0;
  scene.let_go = 10.5 * scene.dt;
  GradientCheckParams params;
  params.vector_step = 3e-8;
  const GradientCheckResult result = gradient_check(resolve(scene), params);
  expect_every_kind_within(result, all_adjoint_parameters().size());
  EXPECT_LE(result.max_relative_error, kTolerance);
}

TEST(GradientCheck, MaterialInPlainCoordinatesWithTheLinearPath) {
  GradientCheckParams params;
  params.log_coordinates = false;
  params.parameters = {AdjointParameter::Stretch, AdjointParameter::Shear,   AdjointParameter::Bend,
                       AdjointParameter::Density, AdjointParameter::Damping, AdjointParameter::HandlePath};
  params.path.basis = HandlePathBasis::PiecewiseLinear;
  params.path.control_points = 5;
  params.frames = {10, 20, 30};  // a loss on a few frames only
  expect_every_kind_within(gradient_check(fast_corner_scene(), params), params.parameters.size());
}

TEST(GradientCheck, HandlesGivenPerStepAlongAFastCircle) {
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = 31;
  const ResolvedScene resolved = resolve(scene);
  // Both handles circle their rest positions once every 0.25 s (radius 5 cm: 1.3 m/s) in the
  // vertical plane across the cloth, in step: fast, without pushing the corners together (which
  // would buckle the cloth, where Newton's branch can switch under any perturbation).
  RolloutInputs inputs;
  inputs.handle_targets.emplace();
  const VecX rest = resolved.grid.rest_positions();
  for (int s = 0; s < scene.frames - 1; ++s) {
    const double phase = 2.0 * M_PI * (s + 1) * scene.dt / 0.25;
    std::vector<Vec3> targets;
    for (int vertex : resolved.handles.vertices)
      targets.push_back(rest.segment<3>(3 * vertex) + 0.05 * Vec3(0.0, 1.0 - std::cos(phase), std::sin(phase)));
    inputs.handle_targets->push_back(targets);
  }
  GradientCheckParams params;
  params.directions = 1;
  expect_every_kind_within(gradient_check(resolved, params, inputs), all_adjoint_parameters().size());
}

TEST(GradientCheck, SelfRepulsionActingOnAFoldingCloth) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 41;
  scene.self_contact = AutoSwitch::Off;
  scene.handles = "corner-center";  // turns self-repulsion on (repulsion = auto, without self-contact)
  resolve_repulsion(scene);
  ASSERT_TRUE(scene.material.repulsion);
  const ResolvedScene resolved = resolve(scene);
  // An out-of-plane push growing down and across the cloth: without it the cloth falls in its
  // plane, a symmetric state that is dynamically unstable, where any perturbation a difference
  // can resolve has left the linear range (docs/design.md §15, "Branches").
  RolloutInputs inputs;
  VecX v0 = VecX::Zero(resolved.grid.dof_count());
  for (int i = 0; i < scene.rows; ++i)
    for (int j = 0; j < scene.cols; ++j) v0[3 * resolved.grid.index(i, j) + 1] = 0.3 * i / 7.0 + 0.5 * j / 7.0;
  inputs.initial_velocities = v0;

  const RecordedRollout rollout = record_rollout(resolved, {}, inputs);
  int repelling = 0;
  for (const RecordedStep& step : rollout.steps) repelling += step.repulsion_energy > 0.0;
  EXPECT_GE(repelling, 5) << "too few steps with pairs inside the repulsion range";

  expect_every_kind_within(gradient_check(resolved, {}, inputs), all_adjoint_parameters().size());
}

// A sphere 2 cm behind the hanging cloth, within the contact range from the start: the barrier
// pushes the cloth off its plane and the lagged friction holds it, the sphere still or moving
// along xyz_v3 (docs/design.md §14, §15: the friction's frozen normal force, tangent plane and
// start depend on x_t too).
TEST(GradientCheck, ContactAndFrictionWithAStillAndAMovingSphere) {
  for (const char* sphere : {"sphere center=0.5,0.12,-0.6 radius=0.1 friction=0.3",
                             "sphere center=0.5,0.12,-0.6 radius=0.1 friction=1 motion=xyz_v3"}) {
    Scene scene;
    scene.rows = scene.cols = 8;
    scene.frames = 31;
    scene.speed = 4.0;
    apply_scene_setting(scene, "obstacle", sphere);
    const ResolvedScene resolved = resolve(scene);
    const RecordedRollout rollout = record_rollout(resolved);
    ASSERT_FALSE(rollout.diverged) << rollout.divergence;
    // Outside the sphere on every frame, and within the barrier's range of it on many.
    const Obstacle& obstacle = resolved.scene.obstacles[0];
    const double range = resolved.scene.contact.range_fraction * resolved.grid.spacing;
    int in_range = 0;
    for (int f = 1; f < rollout.frame_count(); ++f) {
      double closest = INFINITY;
      for (int v = 0; v < resolved.grid.vertex_count(); ++v)
        closest =
            std::min(closest, obstacle.distance(rollout.positions[f].segment<3>(3 * v), obstacle.offset(f * scene.dt)));
      EXPECT_GT(closest, resolved.scene.contact.thickness) << sphere << ", frame " << f;
      in_range += closest < resolved.scene.contact.thickness + range;
    }
    EXPECT_GE(in_range, 12) << sphere;
    expect_every_kind_within(gradient_check(resolved), all_adjoint_parameters().size());
  }
}

// Hung from opposite corners the cloth is compressed flat and Newton's steps end at saddles of
// their energy, on the symmetric branch (docs/design.md §6). The material keeps the symmetry and
// its gradient is that branch's; perturbations that break the symmetry grow along the negative
// curvature, so differences along them leave the linear range at any usable step (not compared).
TEST(GradientCheck, ThroughSaddlesTheMaterialGradientIsTheRecordedBranchs) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 31;
  scene.speed = 4.0;
  scene.handles = "diagonal";
  GradientCheckParams params;
  params.parameters = {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Bend,
                       AdjointParameter::Density, AdjointParameter::Damping};
  const GradientCheckResult result = gradient_check(resolve(scene), params);
  EXPECT_EQ(result.status, AdjointStatus::ThroughSaddles);
  EXPECT_GT(result.saddle_steps, 0);
  expect_every_kind_within(result, params.parameters.size());
}

TEST(GradientCheck, ALossFrameOutsideTheRolloutIsAnError) {
  GradientCheckParams params;
  params.frames = {31};
  EXPECT_THROW(gradient_check(fast_corner_scene(), params), Error);
}

TEST(GradientCheck, ACheckpointedBaseIsRefused) {
  GradientCheckParams params;
  params.record.checkpoint_interval = 5;
  EXPECT_THROW(gradient_check(fast_corner_scene(), params), Error);
}

}  // namespace
}  // namespace fnopt
