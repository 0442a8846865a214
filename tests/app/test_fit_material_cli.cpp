// fnopt fit-material as a user runs it: help, bad ranges, and a tiny fit that writes a material
// file which simulate reads back with --material.
#include <gtest/gtest.h>

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
  const CommandResult coefficient = run_fnopt("fit-material --reference " + reference + " --fit density");
  EXPECT_NE(coefficient.status, 0);
  EXPECT_NE(coefficient.output.find("unknown coefficient 'density'"), std::string::npos) << coefficient.output;
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
  const CommandResult fit = run_fnopt("fit-material --reference " + reference +
                                      " --fit damping --max-evaluations 4 --cd-samples 500 --out " + material);
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("fitted:"), std::string::npos) << fit.output;
  const std::string text = read_text(material);
  EXPECT_NE(text.find("# fitted by fnopt fit-material (damping)"), std::string::npos) << text;
  EXPECT_NE(text.find("damping = "), std::string::npos) << text;
  const CommandResult use = run_fnopt("simulate --res 6 --frames 2 --optimizer newton --threads 1 --material " +
                                      material + " --out " + (dir / "use.h5").string());
  EXPECT_EQ(use.status, 0) << use.output;
}

}  // namespace
