// The gradient-based material fit recovers a hidden material from a rollout's positions, and
// refuses coefficients it cannot fit.
#include <gtest/gtest.h>

#include <fnopt/fits/material_fit_gradient.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

TEST(MaterialFitGradient, RecoversAHiddenMaterialFromTwentyFiveFrames) {
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = 26;
  scene.speed = 4.0;
  Scene hidden = scene;
  hidden.material.stretch *= 1.6;
  hidden.material.shear *= 0.6;
  hidden.material.damping *= 1.4;
  const RecordedRollout truth = record_rollout(resolve(hidden));
  GradientFitTarget target;
  target.scene = resolve(scene);
  for (int f = 1; f < scene.frames; ++f) target.positions.push_back({f, truth.positions[f]});

  int evaluations = 0;
  const GradientMaterialFitResult fit =
      fit_material_by_gradient({target}, scene.material, {}, [&](int evaluation, const Material&, double loss) {
        EXPECT_EQ(evaluation, ++evaluations);
        EXPECT_TRUE(std::isfinite(loss));
      });
  EXPECT_EQ(fit.status, BoundedLbfgsStatus::Converged) << to_string(fit.status);
  EXPECT_EQ(fit.rollouts, evaluations);
  EXPECT_LT(fit.loss, 1e-2 * fit.start_loss);
  EXPECT_NEAR(fit.material.stretch / hidden.material.stretch, 1.0, 0.01);
  EXPECT_NEAR(fit.material.shear / hidden.material.shear, 1.0, 0.01);
  EXPECT_NEAR(fit.material.damping / hidden.material.damping, 1.0, 0.01);
  EXPECT_EQ(fit.material.bend, scene.material.bend);
}

TEST(MaterialFitGradient, OnlyMaterialCoefficientsOnceEachWithAnIntervalCanBeFitted) {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 3;
  GradientFitTarget target;
  target.scene = resolve(scene);
  GradientMaterialFitParams params;
  params.fit = {AdjointParameter::Gravity};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); }, "fit: "));
  params.fit = {AdjointParameter::Shear, AdjointParameter::Shear};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); },
                                    "fit: shear is named twice"));
  params.fit = {AdjointParameter::Shear};
  params.ranges[AdjointParameter::Shear] = {2.0, 1.0};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); }, "range: "));
}

}  // namespace
}  // namespace fnopt
