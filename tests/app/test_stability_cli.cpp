// `fnopt stability` as a user runs it: help, the case list, a tiny run that writes the CSV, the
// plot and the report, and an unknown case rejected in one line.
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

namespace {

TEST(StabilityCli, HelpAndCaseList) {
  const CommandResult help = run_fnopt("stability --help");
  EXPECT_EQ(help.status, 0) << help.output;
  EXPECT_NE(help.output.find("Usage"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--list-cases"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("150"), std::string::npos) << help.output;  // the default frames, explained
  const CommandResult list = run_fnopt("stability --list-cases");
  EXPECT_EQ(list.status, 0) << list.output;
  for (const char* name :
       {"baseline", "stretch-x1000", "soft", "bend-x0.01", "speed-x4", "dt-1/240", "handles-single-center", "grid-200"})
    EXPECT_NE(list.output.find(name), std::string::npos) << name << "\n" << list.output;
}

TEST(StabilityCli, TinyRunWritesTableplotAndReport) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_stability_cli";
  std::filesystem::remove_all(dir);
  const CommandResult r = run_fnopt("stability --out " + dir.string() +
                                    " --cases baseline,bend-x100 --frames 5 --res 8 --optimizers newton,gd "
                                    "--iters-for gd=20 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_TRUE(std::filesystem::exists(dir / "stability.csv"));
  ASSERT_TRUE(std::filesystem::exists(dir / "stability.svg"));
  ASSERT_TRUE(std::filesystem::exists(dir / "report.md"));
  const std::string csv = read_text(dir / "stability.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv;  // header + 2 cases x 2 optimizers
  EXPECT_NE(csv.find("baseline,newton"), std::string::npos) << csv;
  EXPECT_NE(csv.find("bend-x100,gd,20,"), std::string::npos) << csv;
  EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
  const std::string report = read_text(dir / "report.md");
  EXPECT_NE(report.find("fnopt stability"), std::string::npos);
  EXPECT_NE(report.find("--cases baseline,bend-x100"), std::string::npos) << report;  // the command line
  EXPECT_NE(report.find("What fails where"), std::string::npos);
  EXPECT_NE(report.find("](stability.svg)"), std::string::npos);
  EXPECT_EQ(report.find("Partial"), std::string::npos);
  EXPECT_NE(read_text(dir / "stability.svg").find("<svg"), std::string::npos);
  EXPECT_NE(r.output.find("what fails where"), std::string::npos) << r.output;  // the table on the console

  // --resume keeps every row and runs nothing again.
  const CommandResult again = run_fnopt("stability --out " + dir.string() +
                                        " --cases baseline,bend-x100 --frames 5 --res 8 --optimizers newton,gd "
                                        "--iters-for gd=20 --threads 1 --resume");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("resuming: 4 finished rows"), std::string::npos) << again.output;
  EXPECT_EQ(read_text(dir / "stability.csv"), csv);

  // Resuming a subset (one case) keeps the other case's rows in the CSV.
  const CommandResult subset = run_fnopt("stability --out " + dir.string() +
                                         " --cases baseline --frames 5 --res 8 --optimizers newton,gd "
                                         "--iters-for gd=20 --threads 1 --resume");
  ASSERT_EQ(subset.status, 0) << subset.output;
  const std::string after = read_text(dir / "stability.csv");
  EXPECT_EQ(std::count(after.begin(), after.end(), '\n'), 5) << after;
  EXPECT_NE(after.find("bend-x100,gd,20,"), std::string::npos) << after;
  std::filesystem::remove_all(dir);
}

TEST(StabilityCli, UnknownCaseIsOneClearLine) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_stability_cli_bad";
  const CommandResult r = run_fnopt("stability --out " + dir.string() + " --cases baseline,nope");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("cases: unknown case 'nope'"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "stability.csv"));
  const CommandResult no_out = run_fnopt("stability --cases baseline");
  EXPECT_EQ(no_out.status, 2) << no_out.output;
  EXPECT_NE(no_out.output.find("out: "), std::string::npos) << no_out.output;
}

}  // namespace
