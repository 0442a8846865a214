// The backward pass's contract beyond its values (those are test_gradient_check.cpp's): what it
// refuses, what it returns for losses whose gradient is known without a rollout, its linearity in
// the loss, the steps it reports, and checkpoints re-simulated to the same gradient.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

ResolvedScene small_scene(const std::string& handles = "corner") {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 31;
  scene.speed = 4.0;
  scene.handles = handles;
  return resolve(scene);
}

VecX random_vector(Eigen::Index size, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  VecX v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = normal(random);
  return v;
}

std::string field_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
    return error.field();
  }
  return "(no error)";
}

TEST(RolloutAdjoint, ARolloutWithNoForwardPassIsRefused) {
  EXPECT_EQ(field_of([] { backpropagate(RecordedRollout{}, {}); }), "rollout");
}

TEST(RolloutAdjoint, ALossOfTheWrongShapeIsRefused) {
  const RecordedRollout rollout = record_rollout(small_scene());
  const Eigen::Index dofs = rollout.positions.front().size();
  EXPECT_EQ(field_of([&] { backpropagate(rollout, {{3, VecX::Zero(dofs - 3)}}); }), "loss");
  EXPECT_EQ(field_of([&] { backpropagate(rollout, {{rollout.frame_count(), VecX::Zero(dofs)}}); }), "loss");
  EXPECT_EQ(field_of([&] { backpropagate(rollout, {{-1, VecX::Zero(dofs)}}); }), "loss");
}

TEST(RolloutAdjoint, ALossOnTheInitialFrameOnlyIsItsOwnGradient) {
  const RecordedRollout rollout = record_rollout(small_scene());
  const VecX w = random_vector(rollout.positions.front().size(), 1);
  const RolloutGradient gradient = backpropagate(rollout, {{0, w}});
  EXPECT_EQ(gradient.initial_positions, w);
  EXPECT_EQ(gradient.initial_velocities.norm(), 0.0);
  EXPECT_EQ(gradient.material.stretch, 0.0);
  EXPECT_EQ(gradient.material.gravity.norm(), 0.0);
  for (const auto& step : gradient.handle_targets)
    for (const Vec3& g : step) EXPECT_EQ(g.norm(), 0.0);
}

TEST(RolloutAdjoint, TheGradientIsLinearInTheLoss) {
  const RecordedRollout rollout = record_rollout(small_scene());
  const Eigen::Index dofs = rollout.positions.front().size();
  const VecX w1 = random_vector(dofs, 1), w2 = random_vector(dofs, 2);
  const RolloutGradient g1 = backpropagate(rollout, {{10, w1}});
  const RolloutGradient g2 = backpropagate(rollout, {{30, w2}});
  const RolloutGradient sum = backpropagate(rollout, {{30, w2}, {10, w1}});
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-10 * std::max(std::abs(a), std::abs(b)); };
  EXPECT_PRED2(near, sum.material.stretch, g1.material.stretch + g2.material.stretch);
  EXPECT_PRED2(near, sum.material.density, g1.material.density + g2.material.density);
  EXPECT_LE((sum.initial_velocities - g1.initial_velocities - g2.initial_velocities).norm(),
            1e-10 * sum.initial_velocities.norm());
}

TEST(RolloutAdjoint, LogCoordinatesAreTheCoefficientTimesTheGradient) {
  const ResolvedScene scene = small_scene();
  const RecordedRollout rollout = record_rollout(scene);
  const RolloutGradient gradient = backpropagate(rollout, {{30, random_vector(scene.grid.dof_count(), 3)}});
  const Material& m = scene.scene.material;
  EXPECT_EQ(gradient.log_material.stretch, m.stretch * gradient.material.stretch);
  EXPECT_EQ(gradient.log_material.shear, m.shear * gradient.material.shear);
  EXPECT_EQ(gradient.log_material.bend, m.bend * gradient.material.bend);
  EXPECT_EQ(gradient.log_material.density, m.density * gradient.material.density);
  EXPECT_EQ(gradient.log_material.damping, m.damping * gradient.material.damping);
  EXPECT_EQ(gradient.log_material.gravity, gradient.material.gravity);
}

TEST(RolloutAdjoint, OneFactorisationAndOneSolvePerStepAtMinima) {
  const RecordedRollout rollout = record_rollout(small_scene());
  ASSERT_EQ(rollout.steps_at(StepStationarity::Minimum), rollout.step_count());
  const RolloutGradient gradient = backpropagate(rollout, {{30, random_vector(rollout.positions[0].size(), 4)}});
  EXPECT_EQ(gradient.status, AdjointStatus::Exact);
  EXPECT_EQ(gradient.factorizations, rollout.step_count());
  EXPECT_EQ(gradient.solves, rollout.step_count());
  EXPECT_GT(gradient.backward_ms, 0.0);
}

// Hung from two opposite corners the cloth falls flat and is compressed in its plane: Newton's
// steps end at saddles of the step's energy (docs/design.md §6), which both passes report.
TEST(RolloutAdjoint, SaddleStepsAreReportedAndCanStopThePass) {
  const RecordedRollout rollout = record_rollout(small_scene("diagonal"));
  std::vector<int> saddles;
  for (int s = 0; s < rollout.step_count(); ++s)
    if (rollout.steps[s].stationarity == StepStationarity::Saddle) {
      saddles.push_back(s);
      EXPECT_GT(rollout.steps[s].negative_eigenvalues, 0);
    }
  ASSERT_FALSE(saddles.empty());

  const std::vector<FrameGradient> loss{{30, random_vector(rollout.positions[0].size(), 5)}};
  const RolloutGradient through = backpropagate(rollout, loss);
  EXPECT_EQ(through.status, AdjointStatus::ThroughSaddles);
  EXPECT_EQ(through.saddle_steps, saddles);
  EXPECT_TRUE(is_complete(through.status));

  AdjointParams stop;
  stop.solve_at_saddles = false;
  const RolloutGradient stopped = backpropagate(rollout, loss, stop);
  EXPECT_EQ(stopped.status, AdjointStatus::StoppedAtSaddle);
  EXPECT_FALSE(is_complete(stopped.status));
  ASSERT_EQ(stopped.saddle_steps.size(), 1u);
  EXPECT_EQ(stopped.saddle_steps.front(), saddles.back());
}

// With checkpoints the record keeps a fraction of the states and the backward pass re-simulates
// every segment (the last one shorter) onto the recorded path: the same gradient.
TEST(RolloutAdjoint, ACheckpointedRecordGivesTheSameGradient) {
  const ResolvedScene scene = small_scene();
  const RecordedRollout whole = record_rollout(scene);
  RecordOptions options;
  options.checkpoint_interval = 7;
  const RecordedRollout checkpointed = record_rollout(scene, options);
  EXPECT_LT(checkpointed.memory_bytes(), whole.memory_bytes() / 2);

  const std::vector<FrameGradient> loss{{30, random_vector(scene.grid.dof_count(), 6)},
                                        {12, random_vector(scene.grid.dof_count(), 7)}};
  const RolloutGradient expected = backpropagate(whole, loss);
  const RolloutGradient gradient = backpropagate(checkpointed, loss);
  EXPECT_EQ(gradient.resimulated_steps, checkpointed.step_count());
  EXPECT_LE(gradient.resimulation_error, 1e-12);
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-8 * std::max(std::abs(a), std::abs(b)); };
  EXPECT_PRED2(near, gradient.material.stretch, expected.material.stretch);
  EXPECT_PRED2(near, gradient.material.damping, expected.material.damping);
  EXPECT_LE((gradient.initial_velocities - expected.initial_velocities).norm(),
            1e-8 * expected.initial_velocities.norm());
  EXPECT_LE((gradient.initial_positions - expected.initial_positions).norm(), 1e-8 * expected.initial_positions.norm());
}

TEST(RolloutAdjoint, CheckpointsNeedNewtonAloneFromRest) {
  const ResolvedScene scene = small_scene();
  RecordOptions options;
  options.checkpoint_interval = 5;
  PqnOptimizer pqn;
  EXPECT_EQ(field_of([&] { record_rollout(scene, pqn, {5, 0.0}, options); }), "checkpoint_interval");
  RolloutInputs inputs;
  inputs.start_accelerations = std::vector<VecX>(scene.scene.frames - 1, VecX::Zero(scene.grid.dof_count()));
  EXPECT_EQ(field_of([&] { record_rollout(scene, options, inputs); }), "checkpoint_interval");
}

ResolvedScene corner_scene(int res, double speed) {
  Scene scene;
  scene.rows = scene.cols = res;
  scene.frames = 31;
  scene.speed = speed;
  return resolve(scene);
}

// A random linear loss on every frame after the first, as the gradient check's.
std::vector<FrameGradient> random_linear_loss(const RecordedRollout& rollout) {
  std::vector<FrameGradient> loss;
  for (int f = 1; f < rollout.frame_count(); ++f)
    loss.push_back({f, random_vector(rollout.positions.front().size(), static_cast<std::uint64_t>(f))});
  return loss;
}

// The central difference of the loss along the start positions' gradient direction d at step e,
// each perturbed step started from the base's acceleration (the branch the adjoint follows), and
// its relative error against the adjoint's |g|.
double difference_error(const ResolvedScene& scene, const RecordedRollout& base,
                        const std::vector<FrameGradient>& loss, const VecX& gradient, double e) {
  auto loss_at = [&](const VecX& start) {
    RolloutInputs inputs;
    inputs.initial_positions = start;
    inputs.start_accelerations = base.accelerations;
    RecordOptions options;
    options.classify_steps = false;
    const RecordedRollout r = record_rollout(scene, options, inputs);
    double value = 0.0;
    for (const FrameGradient& term : loss) value += term.gradient.dot(r.positions[term.frame]);
    return value;
  };
  const VecX d = gradient.normalized();
  const double difference =
      (loss_at(base.positions.front() + e * d) - loss_at(base.positions.front() - e * d)) / (2.0 * e);
  return std::abs(difference - gradient.norm()) / gradient.norm();
}

// The verdict's R_0 against central differences along the start positions' gradient, on two scenes
// whose R_0 differ by a hundredfold (a slow 8² cloth buckling under its handles, and 10² with the
// handles four times faster): a thirtieth of R_0 agrees within 1 %, thirty times R_0 is off by more
// than 10 %: R_0 is where the linearisation stops holding, to within the factor of thirty.
TEST(RolloutAdjoint, TheVerdictsRadiusIsWhereCentralDifferencesStopAgreeing) {
  double radii[2];
  int i = 0;
  for (const auto& [res, speed] : {std::pair{8, 1.0}, std::pair{10, 4.0}}) {
    const ResolvedScene scene = corner_scene(res, speed);
    const RecordedRollout base = record_rollout(scene);
    const std::vector<FrameGradient> loss = random_linear_loss(base);
    const RolloutGradient gradient = backpropagate(base, loss);
    const double radius = gradient.verdict.start_radius;
    radii[i++] = radius;
    ASSERT_EQ(gradient.verdict.conditioning, GradientConditioning::IllConditioned) << res;
    EXPECT_LT(difference_error(scene, base, loss, gradient.initial_positions, radius / 30.0), 1e-2) << res;
    EXPECT_GT(difference_error(scene, base, loss, gradient.initial_positions, radius * 30.0), 0.1) << res;
  }
  EXPECT_GT(radii[1] / radii[0], 30.0);
}

// A small cloth pulled along is well conditioned; a buckling one is not; a cloth that buckles from a
// symmetric rest amplifies a start perturbation beyond what its own solves resolve; without the
// verdict, nothing is measured. Every kind's radius is the loss radius over its gradient's norm.
TEST(RolloutAdjoint, TheVerdictSeparatesWellFromIllConditionedFromBelowPrecision) {
  auto verdict_of = [](int res, double speed, bool verdict) {
    const RecordedRollout rollout = record_rollout(corner_scene(res, speed));
    AdjointParams params;
    params.verdict = verdict;
    return backpropagate(rollout, random_linear_loss(rollout), params);
  };
  const RolloutGradient well = verdict_of(6, 4.0, true);
  EXPECT_EQ(well.verdict.conditioning, GradientConditioning::WellConditioned);
  EXPECT_GE(well.verdict.start_radius, GradientVerdict::well_conditioned_fraction * 1.0 / 5.0);
  EXPECT_NEAR(well.verdict.radius(well.initial_positions.norm()), well.verdict.start_radius,
              1e-12 * well.verdict.start_radius);
  EXPECT_NEAR(well.verdict.radius(2.0), well.verdict.loss_radius / 2.0, 1e-12 * well.verdict.loss_radius);
  EXPECT_TRUE(std::isinf(well.verdict.radius(0.0)));
  const RolloutGradient ill = verdict_of(12, 4.0, true);
  EXPECT_EQ(ill.verdict.conditioning, GradientConditioning::IllConditioned);
  EXPECT_LT(ill.verdict.start_radius, 1e-3 * well.verdict.start_radius);
  EXPECT_GT(ill.verdict.log_growth, well.verdict.log_growth + std::log(100.0));
  EXPECT_EQ(verdict_of(10, 1.0, true).verdict.conditioning, GradientConditioning::BelowPrecision);
  EXPECT_EQ(verdict_of(6, 4.0, false).verdict.conditioning, GradientConditioning::NotMeasured);
}

// Forward mode against reverse mode: tangents along each ln k (StepLinearization::advance_tangent
// with the source log_material_derivative) give the loss's dL/dln k as sum_f w_f . dx_f/dln k,
// the backward pass's log_material, to rounding (handles held, damping on, every coefficient).
TEST(RolloutAdjoint, TangentsAlongTheMaterialGiveTheAdjointsGradient) {
  const ResolvedScene scene = corner_scene(8, 4.0);
  const RecordedRollout rollout = record_rollout(scene);
  const std::vector<FrameGradient> loss = random_linear_loss(rollout);
  const RolloutGradient adjoint = backpropagate(rollout, loss);
  StepLinearization step(scene);
  const Eigen::Index dofs = rollout.positions.front().size();
  for (AdjointParameter k : {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Bend,
                             AdjointParameter::Density, AdjointParameter::Damping}) {
    VecX dx = VecX::Zero(dofs), dv = VecX::Zero(dofs), source;
    double tangent = 0.0;
    for (int s = 0; s < rollout.step_count(); ++s) {
      step.set_released(rollout.steps[s].released);
      step.linearize(rollout.positions[s], rollout.velocities[s], rollout.accelerations[s], s * scene.scene.dt);
      step.log_material_derivative(k, source);
      step.advance_tangent(dx, dv, &source);
      tangent += loss[s].gradient.dot(dx);  // loss[s] is frame s + 1's
    }
    const double expected = adjoint.log_material.coefficient(k);
    EXPECT_NEAR(tangent, expected, 1e-8 * std::abs(expected)) << to_string(k);
  }
}

// The verdict's forward pass over a checkpointed record re-simulates its segments in order: the
// same verdict as over the full record.
TEST(RolloutAdjoint, ACheckpointedRecordGivesTheSameVerdict) {
  const ResolvedScene scene = corner_scene(6, 4.0);
  RecordOptions checkpoints;
  checkpoints.checkpoint_interval = 5;
  const RecordedRollout full = record_rollout(scene), sparse = record_rollout(scene, checkpoints);
  const GradientVerdict a = backpropagate(full, random_linear_loss(full)).verdict;
  const GradientVerdict b = backpropagate(sparse, random_linear_loss(full)).verdict;
  EXPECT_NEAR(b.start_radius, a.start_radius, 1e-6 * a.start_radius);
  EXPECT_EQ(b.binding_frame, a.binding_frame);
}

}  // namespace
}  // namespace fnopt
