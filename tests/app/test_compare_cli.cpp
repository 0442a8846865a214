// fnopt compare as a user runs it: a small non-square comparison writes its CSV, plot and
// report; a malformed resolution is one clear error line and a non-zero exit.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include "tests/app/run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/util/parse_text.hpp>

namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

// The line of compare.csv whose method is `method` ("" if none).
std::string row_of(const std::filesystem::path& csv, const std::string& method) {
  std::istringstream lines(read_text(csv));
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(method + ",", 0) == 0) return line;
  return "";
}

TEST(CompareCli, ANonSquareComparisonWritesCsvPlotAndReport) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_compare_cli";
  std::filesystem::remove_all(dir);
  const CommandResult r = run_fnopt(
      "compare --res 12x16 --frames 4 --optimizers newton,lbfgs --iters 5 --threads 1 "
      "--step-samples 2 --cd-samples 500 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_TRUE(std::filesystem::exists(dir / "compare.csv"));
  ASSERT_TRUE(std::filesystem::exists(dir / "compare.svg"));
  ASSERT_TRUE(std::filesystem::exists(dir / "report.md"));
  const std::string csv = read_text(dir / "compare.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;  // header, newton, lbfgs N=5
  EXPECT_NE(csv.find("lbfgs,5,,,12x16,"), std::string::npos) << csv;
  const std::string report = read_text(dir / "report.md");
  EXPECT_NE(report.find("compare --res 12x16 --frames 4"), std::string::npos) << report;  // the command line
  EXPECT_NE(report.find("12x16 (192 vertices)"), std::string::npos) << report;            // a table per resolution
  EXPECT_NE(report.find("| lbfgs | 5 |"), std::string::npos) << report;
  EXPECT_NE(report.find("compare.svg"), std::string::npos) << report;

  // Resuming with other optimizers (newton resumed, gd new) keeps lbfgs's row in the CSV.
  const CommandResult subset = run_fnopt(
      "compare --res 12x16 --frames 4 --optimizers newton,gd --iters 5 --lr-gd 1 "
      "--threads 1 --step-samples 2 --cd-samples 500 --resume --out " +
      dir.string());
  ASSERT_EQ(subset.status, 0) << subset.output;
  const std::string after = read_text(dir / "compare.csv");
  EXPECT_EQ(std::count(after.begin(), after.end(), '\n'), 4) << after;
  EXPECT_NE(after.find("gd,5,"), std::string::npos) << after;
  EXPECT_NE(after.find("lbfgs,5,,,12x16,"), std::string::npos) << after;

  // A run computed before resumed ones (newton dropped from the CSV, gd resumed after it): the
  // CSV written at the end holds every row, the resumed ones after the last computed one too.
  std::string without_newton;
  std::istringstream lines(after);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("newton,", 0) != 0) without_newton += line + "\n";
  std::ofstream(dir / "compare.csv") << without_newton;
  const CommandResult again = run_fnopt(
      "compare --res 12x16 --frames 4 --optimizers newton,gd --iters 5 --lr-gd 1 "
      "--threads 1 --step-samples 2 --cd-samples 500 --resume --out " +
      dir.string());
  ASSERT_EQ(again.status, 0) << again.output;
  const std::string last = read_text(dir / "compare.csv");
  EXPECT_EQ(std::count(last.begin(), last.end(), '\n'), 4) << last;
  for (const char* row : {"newton,", "gd,5,", "lbfgs,5,"})
    EXPECT_NE(last.find(row), std::string::npos) << row << "\n" << last;
  std::filesystem::remove_all(dir);
}

// A run that diverged has no error to show (over its first frames it would look better than
// every run that finished), is not on the frontier, and is marked; strain is in percent.
TEST(CompareCli, ADivergedRunLeavesItsErrorsEmptyAndIsOffTheFrontier) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "c";
  const CommandResult r = run_fnopt(
      "compare --res 16 --frames 6 --optimizers adam,pqn,newton --iters 1 --lr-adam 1000 "
      "--threads 1 --step-samples 2 --cd-samples 200 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string csv = read_text(dir / "compare.csv");
  EXPECT_NE(csv.find(",max_strain_pct,min_obstacle_distance_m,min_cloth_distance_m,self_intersections,"
                     "mesh_intersections,diverged,frontier,"),
            std::string::npos)
      << csv;
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  const std::vector<std::string> header = split_csv(line);
  auto cell = [&](const std::vector<std::string>& row, const std::string& column) {
    return row.at(std::find(header.begin(), header.end(), column) - header.begin());
  };
  bool saw_adam = false;
  while (std::getline(lines, line)) {
    const std::vector<std::string> row = split_csv(line);
    if (row[0] == "adam") {
      saw_adam = true;
      EXPECT_EQ(cell(row, "frames"), "1/6") << line;  // the frames it kept
      EXPECT_EQ(cell(row, "e_cd_x1e3"), "") << line;
      EXPECT_EQ(cell(row, "e_3d_x1e2"), "") << line;
      EXPECT_EQ(cell(row, "diverged"), "yes") << line;
      EXPECT_EQ(cell(row, "frontier"), "no") << line;
      EXPECT_GT(std::stod(cell(row, "max_strain_pct")), 300.0) << line;
    }
    if (row[0] == "pqn") {  // one pqn iteration costs a tenth of a 16^2 Newton step: a margin for a loaded machine
      EXPECT_EQ(cell(row, "frontier"), "yes") << line;
    }
  }
  EXPECT_TRUE(saw_adam) << csv;
  const std::string report = read_text(dir / "report.md");
  EXPECT_NE(report.find("The error-time frontier"), std::string::npos) << report;
  EXPECT_NE(report.find("6 frames at dt"), std::string::npos) << report;
  EXPECT_NE(report.find("per-step error on 2 reference states"), std::string::npos) << report;
  EXPECT_NE(report.find("residual acceleration <= " +
                        fnopt::number_text(fnopt::NewtonOptimizer::reference_solve_options().acceleration_tolerance) +
                        " m/s^2"),
            std::string::npos)
      << report;  // the reference's stop, as it ran
  EXPECT_NE(r.output.find("fastest at 16^2"), std::string::npos) << r.output;
}

TEST(CompareCli, AMalformedResolutionIsOneClearErrorLine) {
  for (const char* res : {"32x", "32,x32"}) {
    const CommandResult r =
        run_fnopt(std::string("compare --res ") + res + " --frames 2 --out /tmp/fnopt_never_written");
    EXPECT_NE(r.status, 0) << res;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find("fnopt: error: res: expected resolutions N (N x N) or RxC"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists("/tmp/fnopt_never_written"));
}

TEST(CompareCli, ThePresetKeepsItsBudgetsForMethodsThatFlagsDoNotName) {
  // --iters-for for one method must not drop the preset's exact coarse Newton (300).
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_compare_preset";
  std::filesystem::remove_all(dir);
  const CommandResult r = run_fnopt(
      "compare --preset superres --res 40 --frames 2 --optimizers newton-interp32,fnopt "
      "--iters-for fnopt=3 --threads 1 --step-samples 1 --cd-samples 100 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string csv = read_text(dir / "compare.csv");
  EXPECT_NE(csv.find("newton-interp32,300,,,40,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("fnopt,3,,,40,"), std::string::npos) << csv;
  std::filesystem::remove_all(dir);
}

// Each learned method gets its own super-resolution table against the interpolation methods.
TEST(CompareCli, TheSuperResolutionTablesCoverEveryLearnedMethod) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt(
      "compare --res 12,16 --frames 2 --optimizers fnopt,fnopt-ss,fnopt-ss-32,fnopt-interp8,pqn --iters "
      "2 "
      "--threads 1 --step-samples 1 --cd-samples 100 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string report = read_text(dir / "report.md");
  EXPECT_NE(report.find("## Zero-shot super-resolution"), std::string::npos) << report;
  for (const std::string learned : {"fnopt", "fnopt-ss", "fnopt-ss-32"}) {
    EXPECT_NE(report.find("### " + learned + " at N = 2"), std::string::npos) << learned << "\n" << report;
    EXPECT_NE(report.find("Super-evaluation (" + learned +
                          " N=2) has a lower e_CD than each interpolation method run "
                          "at the same N at "),
              std::string::npos)
        << learned << "\n"
        << report;
  }
  EXPECT_EQ(report.find("### pqn at N"), std::string::npos) << report;
  EXPECT_TRUE(std::filesystem::exists(dir / "superres.svg"));
}

// Only the reference method's converged run is the reference rollout itself: newton-min, also run
// to its tolerance, runs on its own and leaves the saddle the reference keeps on xz_v2.
TEST(CompareCli, NewtonMinIsRunNotTakenFromTheReference) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt(
      "compare --res 12 --motions xz_v2 --frames 50 --optimizers newton,newton-min --threads 1 --step-samples 2 "
      "--cd-samples 100 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string newton = row_of(dir / "compare.csv", "newton");
  const std::string newton_min = row_of(dir / "compare.csv", "newton-min");
  EXPECT_NE(newton.find("the reference rollout itself"), std::string::npos) << newton;
  ASSERT_FALSE(newton_min.empty());
  EXPECT_EQ(newton_min.find("the reference rollout itself"), std::string::npos) << newton_min;
  const auto fields = split_csv(newton_min);
  EXPECT_GT(std::stod(fields[13]), 0.0) << "e_3D of newton-min against the reference: " << newton_min;
}

// --reference newton-min: every error is measured against the rollout that ends at minima, so the
// newton-min run reproduces it (the same solver on the same scene) and Newton's saddles show as error.
TEST(CompareCli, TheNewtonMinReferenceMeasuresAgainstMinima) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt(
      "compare --res 12 --motions xz_v2 --frames 50 --optimizers newton,newton-min --reference newton-min "
      "--threads 1 --step-samples 2 --cd-samples 100 --out " +
      dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string newton = row_of(dir / "compare.csv", "newton");
  const std::string newton_min = row_of(dir / "compare.csv", "newton-min");
  ASSERT_FALSE(newton.empty());
  ASSERT_FALSE(newton_min.empty());
  EXPECT_EQ(newton.find("the reference rollout itself"), std::string::npos) << newton;
  EXPECT_EQ(std::stod(split_csv(newton_min)[13]), 0.0) << newton_min;
  EXPECT_GT(std::stod(split_csv(newton)[13]), 0.0) << newton;
  EXPECT_NE(read_text(dir / "report.md").find("newton-min (Newton that ends at minima)"), std::string::npos);
  const CommandResult bad = run_fnopt("compare --res 12 --reference lbfgs --out " + (tmp.path() / "bad").string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("--reference"), std::string::npos) << bad.output;
}

TEST(CompareCli, AnUnknownPresetIsRejected) {
  const CommandResult r = run_fnopt("compare --preset nope --out /tmp/fnopt_never_written");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("preset"), std::string::npos) << r.output;
}

}  // namespace
