// fnopt repulsion-study as a user runs it: help, a tiny study that writes its CSV and report,
// and the self-repulsion line of fnopt simulate.
#include <gtest/gtest.h>

#include "tests/app/run_fnopt.hpp"
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace {

TEST(RepulsionStudy, HasHelp) {
  const CommandResult r = run_fnopt("repulsion-study --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.output.find("Usage"), std::string::npos);
  EXPECT_NE(r.output.find("--optimizers"), std::string::npos);
}

TEST(RepulsionStudy, ATinyRunWritesTheCsvReportAndPlot) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_repulsion_study";
  std::filesystem::remove_all(dir);
  const CommandResult r = run_fnopt("repulsion-study --out " + dir.string() +
                             " --frames 5 --res 10 --optimizers newton,fnopt --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string csv = read_text(dir / "repulsion.csv");
  // Header + 3 presets x off/on x 2 optimizers.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13) << csv;
  EXPECT_NE(csv.find("corner-center,on,newton"), std::string::npos) << csv;
  EXPECT_NE(csv.find("single-mid-edge,off,fnopt"), std::string::npos) << csv;
  EXPECT_NE(csv.find("corner,on,fnopt"), std::string::npos) << csv;
  const std::string report = read_text(dir / "report.md");
  EXPECT_NE(report.find("# Self-repulsion study"), std::string::npos) << report;
  EXPECT_NE(report.find("repulsion.svg"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "repulsion.svg"));
  EXPECT_NE(r.output.find("mean E_rep"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

TEST(RepulsionStudy, RejectsAnUnknownOptimizer) {
  const CommandResult r = run_fnopt("repulsion-study --out /tmp/fnopt_never --optimizers magic");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("optimizer"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists("/tmp/fnopt_never"));
}

TEST(Simulate, PrintsTheResolvedRepulsion) {
  const auto out = (std::filesystem::temp_directory_path() / "fnopt_test_repulsion_sim.h5").string();
  CommandResult r = run_fnopt("simulate --optimizer newton --res 8 --frames 2 --handles corner-center --out " + out);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("self-repulsion: on (repulsion = auto)"), std::string::npos) << r.output;
  r = run_fnopt("simulate --optimizer newton --res 8 --frames 2 --handles corner-center --no-repulsion --out " + out);
  EXPECT_NE(r.output.find("self-repulsion: off (repulsion = false)"), std::string::npos) << r.output;
  r = run_fnopt("simulate --optimizer newton --res 8 --frames 2 --repulsion --out " + out);
  EXPECT_NE(r.output.find("self-repulsion: on (repulsion = true)"), std::string::npos) << r.output;
  r = run_fnopt("simulate --res 8 --frames 2 --repulsion --no-repulsion --out " + out);
  EXPECT_NE(r.status, 0);
  std::filesystem::remove(out);
}

}  // namespace
