// The gradient-based material fit recovers a hidden material from a rollout's positions, and
// refuses coefficients it cannot fit.
#include <gtest/gtest.h>

#include <fnopt/fits/material_fit_gradient.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TEST(GradientMaterialFit, RecoversAHiddenMaterialFromTwentyFiveFrames) {
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = 26;
  scene.speed = 4.0;
  Scene hidden = scene;
  hidden.material.stretch *= 1.6;
  hidden.material.shear *= 0.6;
  hidden.material.damping *= 1.4;
  const RecordedRollout truth = record_rollout(resolve(hidden));
  std::vector<FramePositions> observed;
  for (int f = 1; f < scene.frames; ++f) observed.push_back({f, truth.positions[f]});

  const GradientMaterialFitResult fit = fit_material_by_gradient(resolve(scene), observed);
  EXPECT_EQ(fit.status, BoundedLbfgsStatus::Converged) << to_string(fit.status);
  EXPECT_NEAR(fit.material.stretch / hidden.material.stretch, 1.0, 0.01);
  EXPECT_NEAR(fit.material.shear / hidden.material.shear, 1.0, 0.01);
  EXPECT_NEAR(fit.material.damping / hidden.material.damping, 1.0, 0.01);
  EXPECT_EQ(fit.material.bend, scene.material.bend);
}

TEST(GradientMaterialFit, OnlyMaterialCoefficientsOnceEachCanBeFitted) {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 3;
  GradientMaterialFitParams params;
  params.fit = {AdjointParameter::Gravity};
  EXPECT_THROW(fit_material_by_gradient(resolve(scene), {}, params), Error);
  params.fit = {AdjointParameter::Shear, AdjointParameter::Shear};
  EXPECT_THROW(fit_material_by_gradient(resolve(scene), {}, params), Error);
  params.fit = {AdjointParameter::Shear};
  params.range = 1.0;
  EXPECT_THROW(fit_material_by_gradient(resolve(scene), {}, params), Error);
}

}  // namespace
}  // namespace fnopt
