// Handle paths fitted to a target shape by the adjoint gradient and by the compass search: the
// gradient recovers a hidden path's target, both keep to their budget and history, and bad input
// is refused.
#include <gtest/gtest.h>

#include <fnopt/fits/handle_path_fit.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

ResolvedScene still_scene() {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 21;
  scene.speed = 4.0;  // xy_v2 four times over: the cloth leaves its flat start (docs/design.md §15)
  return resolve(scene);
}

// The last frame of the rollout whose path has the given offsets.
FramePositions target_of(const ResolvedScene& scene, const HandlePathFitParams& params,
                         const HandleControlPoints& control) {
  const HandlePath path(params.path, scene.scene.frames - 1, static_cast<int>(scene.handles.vertices.size()));
  RolloutInputs inputs;
  inputs.handle_targets = path.targets(scene, control);
  const RecordedRollout rollout = record_rollout(scene, params.record, inputs);
  return {scene.scene.frames - 1, rollout.positions.back()};
}

HandleControlPoints hidden_control() {
  HandleControlPoints control(2, std::vector<Vec3>(3, Vec3::Zero()));
  control[0][2] = Vec3(0.0, 0.04, 0.06);
  control[1][1] = Vec3(0.05, 0.0, -0.03);
  control[1][2] = Vec3(0.02, -0.05, 0.0);
  return control;
}

TEST(HandlePathFit, TheGradientBringsTheClothToAHiddenPathsShape) {
  const ResolvedScene scene = still_scene();
  HandlePathFitParams params;
  params.path.control_points = 3;
  params.passes = 40;
  const FramePositions target = target_of(scene, params, hidden_control());
  const HandlePathFitResult fit = fit_handle_path(scene, {target}, HandlePathFitMethod::Gradient, params);
  EXPECT_GT(fit.start_loss, 0.0);
  EXPECT_LT(fit.loss, 1e-3 * fit.start_loss);
  EXPECT_LE(fit.passes, params.passes);
  EXPECT_EQ(fit.passes, 2 * fit.evaluations);
  EXPECT_EQ(fit.inexact_gradients, 0);
  // The history is the best loss so far, pass by pass, ending at the result.
  ASSERT_EQ(static_cast<int>(fit.history.size()), fit.evaluations);
  for (std::size_t i = 1; i < fit.history.size(); ++i) {
    EXPECT_EQ(fit.history[i].passes, fit.history[i - 1].passes + 2);
    EXPECT_LE(fit.history[i].loss, fit.history[i - 1].loss);
  }
  EXPECT_EQ(fit.history.front().loss, fit.start_loss);
  EXPECT_EQ(fit.history.back().loss, fit.loss);
  // The result's loss is the loss of its path's rollout.
  const FramePositions reached = target_of(scene, params, fit.control);
  EXPECT_NEAR((reached.positions - target.positions).squaredNorm(), fit.loss, 1e-9 * fit.start_loss);
}

// With smoothing, each gradient evaluation is a pass at the point and a forward and a backward pass
// per sample, the history still records the loss at the point, and on this smooth scene a small
// sigma still brings the cloth close to the hidden shape.
TEST(HandlePathFit, TheSmoothedGradientCountsItsSamplesAndStillFits) {
  const ResolvedScene scene = still_scene();
  HandlePathFitParams params;
  params.path.control_points = 3;
  params.passes = 60;
  params.smoothing.sigma = 1e-3;
  params.smoothing.samples = 2;
  const FramePositions target = target_of(scene, params, hidden_control());
  const HandlePathFitResult fit = fit_handle_path(scene, {target}, HandlePathFitMethod::Gradient, params);
  EXPECT_EQ(fit.passes, 5 * fit.evaluations);
  EXPECT_LE(fit.passes, params.passes);
  EXPECT_LT(fit.loss, 1e-2 * fit.start_loss);
  EXPECT_GT(fit.standard_error, 0.0);
  const FramePositions reached = target_of(scene, params, fit.control);
  EXPECT_NEAR((reached.positions - target.positions).squaredNorm(), fit.loss, 1e-9 * fit.start_loss);
  params.smoothing.samples = 3;
  EXPECT_THROW(fit_handle_path(scene, {target}, HandlePathFitMethod::Gradient, params), Error);
}

TEST(HandlePathFit, TheCompassSearchLowersTheLossWithinItsBudget) {
  const ResolvedScene scene = still_scene();
  HandlePathFitParams params;
  params.path.control_points = 3;
  params.passes = 24;
  const FramePositions target = target_of(scene, params, hidden_control());
  int seen = 0;
  const HandlePathFitResult fit = fit_handle_path(scene, {target}, HandlePathFitMethod::Compass, params,
                                                  [&](const HandlePathFitPoint& point) { seen = point.passes; });
  EXPECT_EQ(fit.passes, params.passes);
  EXPECT_EQ(fit.evaluations, params.passes);
  EXPECT_EQ(seen, params.passes);
  EXPECT_EQ(fit.stop, "evaluation-budget");
  EXPECT_LT(fit.loss, fit.start_loss);
}

TEST(HandlePathFit, RefusesBadInput) {
  const ResolvedScene scene = still_scene();
  HandlePathFitParams params;
  EXPECT_THROW(fit_handle_path(scene, {}, HandlePathFitMethod::Gradient, params), Error);
  EXPECT_THROW(fit_handle_path(scene, {{20, VecX::Zero(5)}}, HandlePathFitMethod::Gradient, params), Error);
  EXPECT_THROW(fit_handle_path(scene, {{21, scene.grid.rest_positions()}}, HandlePathFitMethod::Gradient, params),
               Error);
  params.bound = 0.0;
  EXPECT_THROW(fit_handle_path(scene, {{20, scene.grid.rest_positions()}}, HandlePathFitMethod::Gradient, params),
               Error);
  EXPECT_THROW(handle_path_fit_method("newton"), Error);
  EXPECT_EQ(handle_path_fit_method("compass"), HandlePathFitMethod::Compass);
}

}  // namespace
}  // namespace fnopt
