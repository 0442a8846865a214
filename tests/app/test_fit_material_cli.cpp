// fnopt fit-material as a user runs it: help, bad ranges, a tiny compass fit that writes a
// material file which simulate reads back with --material, and a gradient fit that recovers a
// hidden material.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/simulation/rollout_file.hpp>

#include "tests/app/run_fnopt.hpp"

namespace {

TEST(FitMaterialCli, HelpAndBadInput) {
  const CommandResult help = run_fnopt("fit-material --help");
  EXPECT_EQ(help.status, 0) << help.output;
  EXPECT_NE(help.output.find("--reference"), std::string::npos);

  const CommandResult missing = run_fnopt("fit-material --reference /nonexistent.h5");
  EXPECT_NE(missing.status, 0);

  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_fit_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string reference = (dir / "ref.h5").string();
  ASSERT_EQ(run_fnopt("simulate --res 6 --frames 8 --dt 1/30 --optimizer newton --threads 1 --out " + reference).status,
            0);
  const CommandResult range = run_fnopt("fit-material --reference " + reference + " --range stretch=3");
  EXPECT_NE(range.status, 0);
  EXPECT_NE(range.output.find("range: expected COEFFICIENT=LOW:HIGH"), std::string::npos) << range.output;
  const CommandResult coefficient =
      run_fnopt("fit-material --method compass --reference " + reference + " --fit density");
  EXPECT_NE(coefficient.status, 0);
  EXPECT_NE(coefficient.output.find("unknown coefficient 'density'"), std::string::npos) << coefficient.output;
  const CommandResult gravity = run_fnopt("fit-material --reference " + reference + " --fit stretch,gravity");
  EXPECT_EQ(gravity.status, 2);
  EXPECT_EQ(gravity.output,
            "fnopt: error: fit: unknown coefficient 'gravity' (choose from stretch, shear, bend, density, damping)\n");
  const CommandResult method = run_fnopt("fit-material --reference " + reference + " --method newton");
  EXPECT_EQ(method.status, 2);
  EXPECT_EQ(method.output, "fnopt: error: method: expected gradient or compass, got 'newton'\n");
  const CommandResult density = run_fnopt("fit-material --reference " + reference + " --range density=2:1");
  EXPECT_EQ(density.status, 2);
  EXPECT_NE(density.output.find("range: 'density=2:1' must be 0 < LOW < HIGH"), std::string::npos) << density.output;
  for (const std::string horizons : {"0.5,x", "0.6,0.3", "1"}) {
    const CommandResult bad = run_fnopt("fit-material --reference " + reference + " --horizons " + horizons);
    EXPECT_EQ(bad.status, 2) << horizons;
    EXPECT_NE(bad.output.find("fnopt: error: horizons: expected"), std::string::npos) << bad.output;
  }
}

TEST(FitMaterialCli, TinyFitWritesAMaterialThatSimulateReads) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_fit_cli_run";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string reference = (dir / "ref.h5").string(), material = (dir / "fitted.txt").string();
  ASSERT_EQ(
      run_fnopt("simulate --res 6 --frames 8 --dt 1/30 --damping 2 --optimizer newton --threads 1 --out " + reference)
          .status,
      0);
  const CommandResult fit =
      run_fnopt("fit-material --reference " + reference +
                " --method compass --fit damping --max-evaluations 4 --cd-samples 500 --out " + material);
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("fitted:"), std::string::npos) << fit.output;
  const std::string text = read_text(material);
  EXPECT_NE(text.find("# fitted by fnopt fit-material --method compass (damping)"), std::string::npos) << text;
  EXPECT_NE(text.find("damping = "), std::string::npos) << text;
  const CommandResult use = run_fnopt("simulate --res 6 --frames 2 --optimizer newton --threads 1 --material " +
                                      material + " --out " + (dir / "use.h5").string());
  EXPECT_EQ(use.status, 0) << use.output;
}

// A 10 x 10 fnopt rollout of a hidden material (stiffer, less damped, denser than the default),
// every step solved to 1e-8 m/s^2, as the reference: the gradient fit, from the default material (never the reference file's), finds
// the ratios of the stiffnesses to the density and the damping, says that the density is held,
// gives each value's uncertainty and how many rollouts it took; naming the density is one line.
TEST(FitMaterialCli, GradientFitRecoversAHiddenMaterialFromAnFnoptRollout) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_fit_cli_gradient";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string reference = (dir / "ref.h5").string(), material = (dir / "fitted.txt").string();
  ASSERT_EQ(run_fnopt("simulate --res 10 --frames 20 --speed 4 --stretch 700 --shear 20 --damping 2.5 --density 0.25 "
                      "--optimizer newton --tolerance 1e-8 --threads 1 --out " +
                      reference)
                .status,
            0);
  const CommandResult density = run_fnopt("fit-material --reference " + reference + " --fit stretch,density");
  EXPECT_EQ(density.status, 2);
  EXPECT_EQ(density.output.rfind("fnopt: error: fit: density is not determined by positions", 0), 0u)
      << density.output;
  EXPECT_EQ(std::count(density.output.begin(), density.output.end(), '\n'), 1) << density.output;
  const CommandResult fit = run_fnopt("fit-material --reference " + reference + " --max-evaluations 30 --cd-samples 2000 --out " +
                                      material + " --threads 1");
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("after the first (an fnopt rollout: vertex for vertex)"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("from default (stretch 473.2 N/m"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("density, held at 0.187 kg/m^2 (the start's; --mass sets it)"), std::string::npos)
      << fit.output;
  EXPECT_NE(fit.output.find("fitted (stationary: "), std::string::npos) << fit.output;
  const auto ratio = [&](const std::string& name) {
    const std::regex line("  " + name + " += ([0-9.e+-]+) +[^ ]+ +\\+- ([0-9.e+-]+) %");
    std::smatch match;
    EXPECT_TRUE(std::regex_search(fit.output, match, line)) << name << "\n" << fit.output;
    EXPECT_LT(std::stod(match[2]), 0.1) << name;
    return std::stod(match[1]);
  };
  EXPECT_NEAR(ratio("stretch/rho") / (700 / 0.25), 1.0, 1e-3);
  EXPECT_NEAR(ratio("shear/rho") / (20 / 0.25), 1.0, 1e-3);
  EXPECT_NEAR(ratio("bend/rho") / (2e-5 / 0.25), 1.0, 1e-3);
  EXPECT_NEAR(ratio("damping") / 2.5, 1.0, 1e-3);
  const std::regex last(
      "e_CD x 10\\^3 = ([0-9.e+-]+) fitted, ([0-9.e+-]+) start material; ([0-9]+) rollouts \\(([0-9]+) "
      "recorded forward \\+ ([0-9]+) tangent passes\\), and 2 Newton rollouts for e_CD\n$");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(fit.output, match, last)) << fit.output;
  EXPECT_LT(std::stod(match[1]), 0.1 * std::stod(match[2])) << fit.output;
  EXPECT_EQ(std::stoi(match[3]), std::stoi(match[4]) + std::stoi(match[5]));
  EXPECT_EQ(match[4], match[5]);
  EXPECT_GE(std::stoi(match[4]), 2);
  const std::string text = read_text(material);
  EXPECT_NE(text.find("# fitted by fnopt fit-material --method gradient (stretch,shear,bend,damping)"),
            std::string::npos)
      << text;
}

// An ARCSim-layout reference (positions, times_s and a motion attribute, no scene; every other
// frame of a hidden material's rollout at dt 1/30): the gradient fit says it uses the Chamfer
// loss on vertices and lands nearer the hidden material's e_CD than the start.
TEST(FitMaterialCli, GradientFitToAnArcsimLayoutFileMinimisesECd) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_fit_cli_arcsim";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string rollout = (dir / "hidden.h5").string(), reference = (dir / "arcsim_N10_xy_v2.h5").string();
  ASSERT_EQ(
      run_fnopt("simulate --res 10 --frames 24 --stretch 700 --damping 2.5 --optimizer newton --threads 1 --out " +
                rollout)
          .status,
      0);
  {
    const fnopt::TrajectoryFrames frames = fnopt::read_trajectory_frames(rollout);
    std::vector<float> positions;
    std::vector<double> times;
    for (std::size_t f = 0; f < frames.positions.size(); f += 2) {
      positions.insert(positions.end(), frames.positions[f].data(),
                       frames.positions[f].data() + frames.positions[f].size());
      times.push_back(frames.times[f]);
    }
    fnopt::Hdf5File file(reference, fnopt::Hdf5File::Mode::Create);
    file.write("positions", {times.size(), 10, 10, 3}, positions.data());
    file.write("times_s", {times.size()}, times.data());
    file.set_attribute("motion", std::string("xy_v2"));
  }
  const CommandResult fit = run_fnopt("fit-material --reference " + reference +
                                      " --fit stretch,damping --max-evaluations 10 --cd-samples 2000 --out " +
                                      (dir / "fitted.txt").string() + " --threads 1");
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("24 steps of 0.01667 s, 13 frames matched, e_CD on 7 (every --cd-stride-th)"),
            std::string::npos)
      << fit.output;
  const std::regex last("e_CD x 10\\^3 = ([0-9.e+-]+) fitted, ([0-9.e+-]+) start material;");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(fit.output, match, last)) << fit.output;
  EXPECT_LT(std::stod(match[1]), std::stod(match[2])) << fit.output;
}

}  // namespace
