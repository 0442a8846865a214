// fnopt repulsion-study as a user runs it: help, a tiny study that writes its CSV and report,
// and the self-repulsion line of fnopt simulate.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include "tests/app/run_fnopt.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

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
  const CommandResult r =
      run_fnopt("repulsion-study --out " + dir.string() + " --frames 5 --res 10 --optimizers newton,fnopt --threads 1");
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

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A row without its ms_per_frame cell (the 7th): the only cell a rerun may change.
std::string without_timing(const std::string& row) {
  std::vector<std::string> cells;
  std::istringstream in(row);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  cells.erase(cells.begin() + 6);
  std::string out;
  for (const auto& cell : cells) out += cell + ",";
  return out;
}

TEST(RepulsionStudy, AResumedStudyRunsOnlyTheMissingRunsAndRedrawsEveryRun) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_repulsion_resume";
  std::filesystem::remove_all(dir);
  const std::string command =
      "repulsion-study --out " + dir.string() + " --frames 4 --res 8 --optimizers newton --threads 1";
  ASSERT_EQ(run_fnopt(command).status, 0);
  const std::vector<std::string> full = lines_of(read_text(dir / "repulsion.csv"));
  const std::string full_energy = read_text(dir / "repulsion_energy.csv");
  ASSERT_EQ(full.size(), 7u);                           // header + 3 presets x off/on
  EXPECT_EQ(lines_of(full_energy).size(), 1u + 6 * 5);  // 5 frames (the rest state too) per run

  // Stop "after" four runs: the last two rows are gone from the run table.
  {
    std::ofstream csv(dir / "repulsion.csv", std::ios::trunc);
    for (std::size_t i = 0; i < 5; ++i) csv << full[i] << "\n";
  }
  const CommandResult r = run_fnopt(command + " --resume");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("resuming: 4 finished runs"), std::string::npos) << r.output;
  const std::vector<std::string> resumed = lines_of(read_text(dir / "repulsion.csv"));
  ASSERT_EQ(resumed.size(), full.size());
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(resumed[i], full[i]) << "kept run " << i;
  for (std::size_t i = 5; i < full.size(); ++i) EXPECT_EQ(without_timing(resumed[i]), without_timing(full[i])) << i;
  EXPECT_EQ(read_text(dir / "repulsion_energy.csv"), full_energy);
  std::filesystem::remove_all(dir);
}

TEST(RepulsionStudy, ResumingWithOtherOptimizersKeepsTheEarlierRuns) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_repulsion_subset";
  std::filesystem::remove_all(dir);
  const std::string command = "repulsion-study --out " + dir.string() + " --frames 2 --res 6 --threads 1";
  ASSERT_EQ(run_fnopt(command + " --optimizers newton").status, 0);
  const std::vector<std::string> newton = lines_of(read_text(dir / "repulsion.csv"));
  const std::vector<std::string> newton_energy = lines_of(read_text(dir / "repulsion_energy.csv"));
  const CommandResult r = run_fnopt(command + " --optimizers gd --resume");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::vector<std::string> both = lines_of(read_text(dir / "repulsion.csv"));
  const std::vector<std::string> both_energy = lines_of(read_text(dir / "repulsion_energy.csv"));
  ASSERT_EQ(both.size(), 1 + 2 * (newton.size() - 1));
  ASSERT_EQ(both_energy.size(), 1 + 2 * (newton_energy.size() - 1));
  for (std::size_t i = 1; i < newton.size(); ++i)
    EXPECT_NE(std::find(both.begin(), both.end(), newton[i]), both.end()) << "dropped: " << newton[i];
  for (std::size_t i = 1; i < newton_energy.size(); ++i)
    EXPECT_NE(std::find(both_energy.begin(), both_energy.end(), newton_energy[i]), both_energy.end())
        << newton_energy[i];
  std::filesystem::remove_all(dir);
}

TEST(RepulsionStudy, ResumingWithoutTheEnergyFileIsOneClearLine) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_repulsion_no_energy";
  std::filesystem::remove_all(dir);
  const std::string command =
      "repulsion-study --out " + dir.string() + " --frames 2 --res 6 --optimizers newton --threads 1";
  ASSERT_EQ(run_fnopt(command).status, 0);
  std::filesystem::remove(dir / "repulsion_energy.csv");
  const CommandResult r = run_fnopt(command + " --resume");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("repulsion_energy.csv is missing"), std::string::npos) << r.output;
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
  EXPECT_NE(r.output.find("self-repulsion: off (repulsion = auto)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("self-contact: on (self-contact = auto)"), std::string::npos) << r.output;
  r = run_fnopt("simulate --optimizer newton --res 8 --frames 2 --handles corner-center --no-self-contact --out " +
                out);
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
