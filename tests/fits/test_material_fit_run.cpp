// fnopt fit-material's run in-process: a gradient fit to an fnopt rollout of a hidden material
// writes a material file that reads back, and bad methods and coefficients are refused by name.
#include <gtest/gtest.h>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/fits/material_fit_run.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

// An fnopt rollout of `scene` by Newton, written to `path`.
void write_reference(const Scene& scene, const std::string& path) {
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  write_rollout_file(path, run_rollout(resolve(scene), newton, options), to_scene_text(scene), newton.settings());
}

// 6 x 6 over 8 steps, the handles four times faster than xy_v2.
Scene small_scene() {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 8;
  scene.speed = 4.0;
  return scene;
}

TEST(MaterialFitRun, AGradientFitWritesAMaterialFileThatReadsBack) {
  const testing::TempDir tmp;
  Scene hidden = small_scene();
  hidden.material.stretch *= 1.5;
  const std::string reference = (tmp.path() / "reference.h5").string();
  write_reference(hidden, reference);
  MaterialFitRun run;
  run.references = {reference};
  run.coefficients = "stretch";
  run.params.max_evaluations = 3;
  run.out = (tmp.path() / "fitted.txt").string();
  ::testing::internal::CaptureStdout();
  run_material_fit(run);
  const std::string printed = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(printed.find("fitted (not stationary: stopped at --max-evaluations"), std::string::npos) << printed;
  EXPECT_NE(printed.find("  stretch/rho  = "), std::string::npos) << printed;
  const Material fitted = material_preset(run.out);
  EXPECT_GT(fitted.stretch, Material{}.stretch);
  EXPECT_EQ(fitted.shear, Material{}.shear);
}

// Positions leave the density free; the cloth's mass sets it: 0.06 kg over the 6 x 6 grid's square
// metre is 0.06 kg/m^2, the fit's density, and the stiffnesses follow their ratios to it.
TEST(MaterialFitRun, TheMassSetsTheDensityThePositionsCannot) {
  const testing::TempDir tmp;
  const Scene hidden = small_scene();
  const std::string reference = (tmp.path() / "reference.h5").string();
  write_reference(hidden, reference);
  MaterialFitRun run;
  run.references = {reference};
  run.mass = 0.06;
  run.out = (tmp.path() / "fitted.txt").string();
  ::testing::internal::CaptureStdout();
  run_material_fit(run);
  const std::string printed = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(printed.find("held at 0.06 kg/m^2 (--mass)"), std::string::npos) << printed;
  const Material fitted = material_preset(run.out);
  EXPECT_DOUBLE_EQ(fitted.density, 0.06);
  EXPECT_NEAR(fitted.stretch / fitted.density, hidden.material.stretch / hidden.material.density,
              1e-3 * hidden.material.stretch / hidden.material.density);
  EXPECT_NEAR(fitted.damping, hidden.material.damping, 1e-3 * hidden.material.damping);
  run.mass = -1.0;
  EXPECT_TRUE(testing::throws_error([&] { run_material_fit(run); }, "mass: must be at least 0"));
}

TEST(MaterialFitRun, RefusesAnUnknownMethodOrCoefficientByName) {
  MaterialFitRun run;
  run.method = "grid";
  EXPECT_TRUE(testing::throws_error([&] { run_material_fit(run); }, "method: expected gradient or compass"));
  run.method = "gradient";
  run.coefficients = "stretch,colour";
  EXPECT_TRUE(testing::throws_error([&] { run_material_fit(run); }, "fit: "));
  run.method = "compass";
  run.coefficients = "density";
  EXPECT_TRUE(testing::throws_error([&] { run_material_fit(run); }, "fit: unknown coefficient 'density'"));
}

}  // namespace
}  // namespace fnopt
