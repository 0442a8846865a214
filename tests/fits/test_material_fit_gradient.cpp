// The gradient-based material fit recovers hidden materials in the coordinates positions determine
// (stiffness over density, and damping), ends at a stationary point with its uncertainty, and
// refuses coefficients it cannot fit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <fnopt/fits/material_fit_gradient.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

constexpr AdjointParameter kStiffnesses[] = {AdjointParameter::Stretch, AdjointParameter::Shear,
                                             AdjointParameter::Bend};

Scene corner_scene(int res, int frames) {
  Scene scene;
  scene.rows = scene.cols = res;
  scene.frames = frames;
  scene.speed = 4.0;
  return scene;
}

GradientFitTarget target_of(const Scene& scene, const Material& hidden) {
  Scene truth_scene = scene;
  truth_scene.material = hidden;
  const RecordedRollout truth = record_rollout(resolve(truth_scene));
  GradientFitTarget target;
  target.scene = resolve(scene);
  for (int f = 1; f < scene.frames; ++f) target.positions.push_back({f, truth.positions[f]});
  return target;
}

// Hidden materials with another density than the start's (so that only the ratios can be found):
// stiffer and less damped; softer with a bend a tenth of the default's; a stiff bend. From the
// default, each fit ends stationary within its default budget, with stretch/rho, shear/rho, bend/rho
// and damping within 0.1 %.
TEST(MaterialFitGradient, RecoversHiddenRatiosToDensityAndDampingFromTheDefault) {
  const Scene scene = corner_scene(12, 26);
  struct Hidden {
    double stretch, shear, bend, density, damping;
  };
  for (const Hidden& h : {Hidden{1.6, 0.6, 1.0, 1.3, 0.7}, Hidden{0.5, 1.5, 0.1, 0.8, 1.5}, Hidden{1.0, 1.0, 8.0, 1.0, 1.2}}) {
    Material hidden = scene.material;
    hidden.stretch *= h.stretch, hidden.shear *= h.shear, hidden.bend *= h.bend;
    hidden.density *= h.density, hidden.damping *= h.damping;
    int evaluations = 0;
    const GradientMaterialFitResult fit =
        fit_material_by_gradient({target_of(scene, hidden)}, scene.material, {},
                                 [&](int evaluation, double, const Material&, double loss) {
                                   EXPECT_EQ(evaluation, ++evaluations);
                                   EXPECT_TRUE(std::isfinite(loss));
                                 });
    EXPECT_EQ(fit.status, BoundedGaussNewtonStatus::Stationary) << to_string(fit.status);
    EXPECT_EQ(fit.rollouts, evaluations);
    EXPECT_LE(evaluations, 30) << "hidden bend x" << h.bend;  // the default budget, over both stages
    EXPECT_EQ(fit.material.density, scene.material.density);
    for (AdjointParameter k : kStiffnesses)
      EXPECT_NEAR((material_coefficient(fit.material, k) / fit.material.density) /
                      (material_coefficient(hidden, k) / hidden.density),
                  1.0, 1e-3)
          << to_string(k) << " of hidden bend x" << h.bend;
    EXPECT_NEAR(fit.material.damping / hidden.damping, 1.0, 1e-3) << h.bend;
    ASSERT_EQ(fit.uncertainty.size(), 4u);
    for (double u : fit.uncertainty) EXPECT_LT(u, 1e-3);
  }
}

// In stages: the first evaluations on a quarter and then half of the steps, the rest on all of them,
// each stage from where the last ended; the result is the whole horizon's stationary point.
TEST(MaterialFitGradient, FitsInStagesOverAGrowingHorizon) {
  const Scene scene = corner_scene(12, 26);
  Material hidden = scene.material;
  hidden.bend *= 0.1, hidden.damping *= 1.5;
  GradientMaterialFitParams params;
  params.horizons = {0.25, 0.5};
  params.optimizer.max_evaluations = 60;  // over the three stages
  std::vector<double> horizons;
  const GradientMaterialFitResult fit = fit_material_by_gradient(
      {target_of(scene, hidden)}, scene.material, params,
      [&](int, double horizon, const Material&, double) { horizons.push_back(horizon); });
  ASSERT_FALSE(horizons.empty());
  EXPECT_EQ(horizons.front(), 0.25);
  EXPECT_EQ(horizons.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(horizons.begin(), horizons.end()));
  EXPECT_NE(std::find(horizons.begin(), horizons.end(), 0.5), horizons.end());
  EXPECT_EQ(fit.status, BoundedGaussNewtonStatus::Stationary) << to_string(fit.status);
  EXPECT_EQ(fit.rollouts, static_cast<int>(horizons.size()));
  EXPECT_NEAR((fit.material.bend / fit.material.density) / (hidden.bend / hidden.density), 1.0, 1e-3);
  for (const std::vector<double>& bad : {std::vector<double>{0.5, 0.25}, std::vector<double>{1.0}}) {
    params.horizons = bad;
    EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target_of(scene, hidden)}, scene.material, params); },
                                      "horizons: expected fractions of the steps ascending in (0, 1)"));
  }
}

// Noise on the observed positions: the fit lands off the hidden values, and the reported standard
// deviations account for it (each error within four of them). The bend, which a 10² cloth's
// positions barely show under 2 mm of noise, is held.
TEST(MaterialFitGradient, TheUncertaintyCoversTheErrorThatNoiseCauses) {
  const Scene scene = corner_scene(10, 21);
  Material hidden = scene.material;
  hidden.stretch *= 1.4, hidden.damping *= 0.8;
  GradientFitTarget target = target_of(scene, hidden);
  std::mt19937_64 random(11);
  std::normal_distribution<double> noise(0.0, 2e-3);  // 2 mm
  for (FramePositions& frame : target.positions)
    for (Eigen::Index i = 0; i < frame.positions.size(); ++i) frame.positions[i] += noise(random);
  GradientMaterialFitParams params;
  params.fit = {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Damping};
  const GradientMaterialFitResult fit = fit_material_by_gradient({target}, scene.material, params);
  EXPECT_EQ(fit.status, BoundedGaussNewtonStatus::Stationary) << to_string(fit.status);
  const double errors[] = {std::log(fit.material.stretch / hidden.stretch), std::log(fit.material.shear / hidden.shear),
                           std::log(fit.material.damping / hidden.damping)};
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(fit.uncertainty[i], 1e-5) << i;
    EXPECT_LT(std::abs(errors[i]), 4.0 * fit.uncertainty[i]) << i << ": " << errors[i] << " +- " << fit.uncertainty[i];
  }
}

TEST(MaterialFitGradient, OnlyIdentifiableMaterialCoefficientsOnceEachWithAnIntervalCanBeFitted) {
  const Scene scene = corner_scene(6, 3);
  GradientFitTarget target;
  target.scene = resolve(scene);
  GradientMaterialFitParams params;
  params.fit = {AdjointParameter::Gravity};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); }, "fit: "));
  params.fit = {AdjointParameter::Shear, AdjointParameter::Shear};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); },
                                    "fit: shear is named twice"));
  params.fit = {AdjointParameter::Stretch, AdjointParameter::Density};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); },
                                    "fit: density is not determined by positions"));
  params.fit = {AdjointParameter::Shear};
  params.ranges[AdjointParameter::Shear] = {2.0, 1.0};
  EXPECT_TRUE(testing::throws_error([&] { fit_material_by_gradient({target}, scene.material, params); }, "range: "));
}

}  // namespace
}  // namespace fnopt
