// fnopt fit-handles as a user runs it (docs/design.md §15): both methods on a hidden path's target
// with their CSV, plot and fitted trajectory, the trajectory replayed by simulate, a rollout file
// as the target, and bad input as one line.
#include <gtest/gtest.h>

#include "run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

TEST(FitHandlesCli, BothMethodsTheirFilesAndAReplay) {
  const fnopt::testing::TempDir tmp;
  const std::string csv = (tmp.path() / "loss.csv").string(), plot = (tmp.path() / "loss.svg").string(),
                    path = (tmp.path() / "path.csv").string();
  const CommandResult fit =
      run_fnopt("fit-handles --res 6 --frames 12 --passes 16 --control-points 2 --threads 1 --csv " + csv + " --plot " +
                plot + " --out " + path);
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("6x6, 12 steps"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("\ngradient loss "), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("\ncompass  loss "), std::string::npos) << fit.output;
  const auto last = fit.output.rfind("loss from ");
  ASSERT_NE(last, std::string::npos) << fit.output;
  EXPECT_EQ(fit.output.find('\n', last), fit.output.size() - 1) << fit.output;

  std::string header;
  const auto rows = csv_rows(csv, header);
  EXPECT_EQ(header, "method,passes,loss_m2");
  int gradient = 0, compass = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 3u);
    gradient += row[0] == "gradient";
    compass += row[0] == "compass";
    EXPECT_LE(std::stoi(row[1]), 16);
  }
  EXPECT_EQ(compass, 17);  // the start, then one row per pass
  EXPECT_GE(gradient, 2);
  EXPECT_NE(read_text(plot).find("<svg"), std::string::npos);

  const auto replay_rows = csv_rows(path, header);
  EXPECT_EQ(header, "t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z");
  EXPECT_EQ(replay_rows.size(), 13u);  // t = 0 and every step
  const CommandResult replay = run_fnopt("simulate --res 6 --frames 12 --optimizer newton --threads 1 --trajectory " +
                                         path + " --out " + (tmp.path() / "replay.h5").string());
  EXPECT_EQ(replay.status, 0) << replay.output;
}

TEST(FitHandlesCli, ARolloutFileAsTheTarget) {
  const fnopt::testing::TempDir tmp;
  const std::string target = (tmp.path() / "target.h5").string();
  const CommandResult made = run_fnopt(
      "simulate --res 6 --frames 12 --motion xy_v2 --speed 4 --optimizer newton "
      "--threads 1 --out " +
      target);
  ASSERT_EQ(made.status, 0) << made.output;
  const CommandResult fit =
      run_fnopt("fit-handles --res 6 --frames 12 --method gradient --passes 8 --threads 1 --target " + target);
  ASSERT_EQ(fit.status, 0) << fit.output;
  EXPECT_NE(fit.output.find("target: frame 12 of " + target), std::string::npos) << fit.output;
  EXPECT_EQ(fit.output.find("\ncompass"), std::string::npos) << fit.output;

  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--res 8 --frames 12 --target " + target, "target: " + target + ": a 6x6 grid, the scene's is 8x8"},
           {"--res 6 --frames 12 --target-frame 13", "target-frame: must be a frame of the rollout, 1 to 12, got 13"},
           {"--res 6 --frames 12 --method newton", "method: expected gradient or compass, got 'newton'"},
           {"--res 6 --frames 12 --passes 1", "passes: must be at least 2 (one forward and one backward pass)"},
       }) {
    const CommandResult bad = run_fnopt("fit-handles " + arguments);
    EXPECT_EQ(bad.status, 2) << arguments << ": " << bad.output;
    EXPECT_EQ(bad.output, "fnopt: error: " + message + "\n") << arguments;
  }
}

}  // namespace
