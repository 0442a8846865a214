// Fitting the material to reference rollouts: the fit recovers the coefficients an fnopt rollout
// was made with, references of both kinds load into the scene that reproduces them, and the
// material file it writes reads back.
#include <fnopt/fits/material_fit.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("fnopt_test_fit_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A small scene whose motion starts within its frames: 9x9 vertices, dt 1/30, 45 steps (1.5 s:
// the drop, then the handles' first swing out).
Scene small_scene() {
  Scene scene;
  scene.rows = scene.cols = 9;
  scene.dt = 1.0 / 30.0;
  scene.frames = 45;
  scene.motion = "xy_v2";
  return scene;
}

std::string write_reference(const std::filesystem::path& dir, const Scene& scene) {
  NewtonOptimizer newton;
  RolloutOptions options;
  // Solved as tightly as the fits below solve their rollouts (newton_tolerance 1e-9), so that the
  // reference's own material reproduces it to rounding.
  options.solve = {NewtonOptimizer::reference_solve_options().max_iterations, 1e-9};
  const RolloutResult rollout = run_rollout(resolve(scene), newton, options);
  EXPECT_FALSE(rollout.diverged);
  const std::string path = (dir / "reference.h5").string();
  write_rollout_file(path, rollout, to_scene_text(scene), newton.settings());
  return path;
}

TEST(MaterialFit, RecoversTheCoefficientsOfAnFnoptRollout) {
  const auto dir = temp_dir("recover");
  Scene truth = small_scene();
  truth.material.stretch = 150.0;
  truth.material.damping = 2.0;
  const FitReference reference = load_fit_reference(write_reference(dir, truth));
  EXPECT_EQ(reference.scene.rows, 9);
  EXPECT_EQ(reference.scene.frames, 45);
  EXPECT_EQ(reference.scene.material.stretch, 150.0);

  Material start = truth.material;
  start.stretch = 90.0;
  start.damping = 3.5;
  MaterialFitParams params;
  params.coefficients = {MaterialCoefficient::Stretch, MaterialCoefficient::Damping};
  params.initial_step = 0.5;
  params.final_step = 0.01;
  params.chamfer.samples = 1000;
  params.chamfer_stride = 1;
  params.newton_tolerance = 1e-9;
  int calls = 0;
  const MaterialFitResult fit =
      fit_material({reference}, start, params, [&](int, const FitEvaluation&, const FitEvaluation&) { ++calls; });
  EXPECT_EQ(calls, fit.evaluations);
  EXPECT_TRUE(fit.converged);
  std::printf("fit: %d rollouts, stretch %.4g (true 150), damping %.4g (true 2)\n", fit.evaluations,
              fit.best.material.stretch, fit.best.material.damping);
  EXPECT_LT(fit.best.mean_error, 0.01 * fit.start.mean_error);
  EXPECT_NEAR(fit.best.material.stretch, 150.0, 0.05 * 150.0);
  EXPECT_NEAR(fit.best.material.damping, 2.0, 0.05 * 2.0);
  // Coefficients that are not fitted stay as they started.
  EXPECT_EQ(fit.best.material.shear, start.shear);
  EXPECT_EQ(fit.best.material.bend, start.bend);
}

TEST(MaterialFit, TheReferencesOwnMaterialHasZeroError) {
  const auto dir = temp_dir("zero");
  const Scene scene = small_scene();
  const FitReference reference = load_fit_reference(write_reference(dir, scene));
  MaterialFitParams params;
  params.newton_tolerance = 1e-9;
  EXPECT_NEAR(evaluate_material({reference}, scene.material, params).mean_error, 0.0, 1e-10);
  Material other = scene.material;
  other.stretch *= 0.5;
  EXPECT_GT(evaluate_material({reference}, other, params).mean_error, 1e-6);
}

TEST(MaterialFit, AnArcsimLayoutFileGivesTheDefaultSceneAtItsResolutionAndMotion) {
  const auto dir = temp_dir("arcsim");
  const std::string path = (dir / "arcsim_N5_rot_h0.h5").string();
  const Grid grid = Grid::make(5, 5, 1.0);
  {
    Hdf5File file(path, Hdf5File::Mode::Create);
    std::vector<float> positions;
    for (int t = 0; t < 4; ++t)
      for (int k = 0; k < grid.rest_positions().size(); ++k) positions.push_back(float(grid.rest_positions()[k]));
    file.write("positions", {4, 5, 5, 3}, positions.data());
    const std::vector<double> times = {0.0, 1.0 / 30, 2.0 / 30, 3.0 / 30};
    file.write("times_s", {4}, times.data());
    file.set_attribute("motion", std::string("rot_h0"));
  }
  const FitReference reference = load_fit_reference(path);
  EXPECT_EQ(reference.scene.rows, 5);
  EXPECT_EQ(reference.scene.cols, 5);
  EXPECT_EQ(reference.scene.motion, "rot_h0");
  EXPECT_EQ(reference.scene.handles, "corner");
  EXPECT_EQ(reference.scene.frames, 6);  // 0.1 s at dt = 1/60

  const std::string foreign = (dir / "foreign.h5").string();
  {
    Hdf5File file(foreign, Hdf5File::Mode::Create);
    std::vector<float> positions(4 * 5 * 5 * 3, 0.0f);
    file.write("positions", {4, 5, 5, 3}, positions.data());
    const std::vector<double> times = {0.0, 0.1, 0.2, 0.3};
    file.write("times_s", {4}, times.data());
  }
  try {
    load_fit_reference(foreign);
    FAIL() << "a file that is neither kind must be rejected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("neither an fnopt rollout"), std::string::npos) << e.what();
  }
}

TEST(MaterialFit, MaterialFileRoundTrip) {
  const auto dir = temp_dir("file");
  Material m;
  m.stretch = 123.456789;
  m.shear = 0.3;
  m.bend = 3.3e-6;
  m.damping = 4.25;
  const std::string path = (dir / "fitted.txt").string();
  write_material_file(path, m, "fitted to\n  a.h5");
  const Material back = material_preset(path);
  EXPECT_EQ(back.stretch, m.stretch);
  EXPECT_EQ(back.shear, m.shear);
  EXPECT_EQ(back.bend, m.bend);
  EXPECT_EQ(back.density, m.density);
  EXPECT_EQ(back.damping, m.damping);
}

TEST(MaterialFit, ParamsAreValidated) {
  MaterialFitParams params;
  params.coefficients = {MaterialCoefficient::Stretch, MaterialCoefficient::Stretch};
  EXPECT_THROW(params.validate(), Error);
  params = {};
  params.final_step = 2 * params.initial_step;
  EXPECT_THROW(params.validate(), Error);
  params = {};
  params.coefficients.clear();
  EXPECT_THROW(params.validate(), Error);
  EXPECT_THROW(material_coefficient("density"), Error);
  EXPECT_EQ(coefficient_name(material_coefficient("bend")), "bend");
}

}  // namespace
}  // namespace fnopt
