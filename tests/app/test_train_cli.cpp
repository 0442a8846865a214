// fnopt train as a user runs it: validation rows and the best model, the same best after a
// resume as in one straight run, and one-line errors for bad validation flags.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

const std::string kTinyModel =
    " --res 8 --envs 4 --batch 2 --width 4 --layers 2 --modes 4 --lifting 8 --projection 4 --threads 1"
    " --checkpoint-every 10 --lr 0.05";
const std::string kTinyRun =
    kTinyModel + " --validate-res 12 --validate-every 10 --validate-frames 12 --validate-motions xy_v2,rot_h0";

// The validation rows without their wall-clock column.
std::vector<std::string> validation_rows(const std::filesystem::path& dir) {
  std::istringstream text(read_text(dir / "validation.csv"));
  std::vector<std::string> rows;
  std::string line;
  while (std::getline(text, line)) {
    const auto first = line.find(','), second = line.find(',', first + 1);
    rows.push_back(line.substr(0, first) + line.substr(second));
  }
  return rows;
}

// The cached Newton references in `dir` named newton_reference_<label><16 hex digits of the hash>.h5
// (simulation/newton_reference.hpp); exact, so that label xyz_v4_ does not count xyz_v4_diagonal_.
int reference_files(const std::filesystem::path& dir, const std::string& label) {
  const std::string prefix = "newton_reference_" + label;
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    files += name.rfind(prefix, 0) == 0 && name.size() == prefix.size() + 16 + 3 && entry.path().extension() == ".h5";
  }
  return files;
}

TEST(TrainCli, ValidatesEveryIntervalAndKeepsTheBestModel) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt("train --out " + dir.string() + " --steps 30 --keep-validated" + kTinyRun);
  ASSERT_EQ(r.status, 0) << r.output;
  for (int step : {10, 20, 30})
    EXPECT_TRUE(std::filesystem::exists(dir / "validated" / ("model-" + std::to_string(step) + ".pt"))) << step;
  const auto rows = validation_rows(dir);
  ASSERT_EQ(rows.size(), 4u) << read_text(dir / "validation.csv");
  EXPECT_EQ(rows[0], "step,resolution,motions,frames,optimizer,iterations,e3d_x1e2,max_strain,diverged,grid_e3d_x1e2");
  EXPECT_EQ(rows[1].rfind("10,12,xy_v2+rot_h0,12,fnopt-ss,10,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[3].rfind("30,", 0), 0u) << rows[3];
  EXPECT_TRUE(std::filesystem::exists(dir / "model-best.pt"));
  EXPECT_NE(r.output.find("best validation: step "), std::string::npos) << r.output;
  // The references are cached next to the log, one file per motion (named by a hash of the scene,
  // Newton's settings and the version: simulation/newton_reference.hpp).
  for (const std::string label : {"validation_12_xy_v2_", "validation_12_rot_h0_"})
    EXPECT_EQ(reference_files(dir, label), 1) << label;
}

TEST(TrainCli, ValidatesOffTheCornersWithHandlePresets) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r =
      run_fnopt("train --out " + dir.string() + " --steps 10" + kTinyModel +
                " --validate-res 12 --validate-every 10 --validate-frames 12 --validate-handles corner,diagonal");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = validation_rows(dir);
  ASSERT_EQ(rows.size(), 2u) << read_text(dir / "validation.csv");
  // The default motions (not the tables' test scenes), each with both presets.
  EXPECT_EQ(rows[1].rfind("10,12,xyz_v4+rot_h1@corner+diagonal,12,fnopt-ss,10,", 0), 0u) << rows[1];
  EXPECT_NE(r.output.find("validation references: 4 solved, 0 cached"), std::string::npos) << r.output;
  for (const std::string label : {"validation_12_xyz_v4_", "validation_12_xyz_v4_diagonal_", "validation_12_rot_h1_",
                                  "validation_12_rot_h1_diagonal_"})
    EXPECT_EQ(reference_files(dir, label), 1) << label;
}

TEST(TrainCli, ValidatesAtSeveralGrids) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt("train --out " + dir.string() + " --steps 10" + kTinyModel +
                                    " --validate-res 10,12 --validate-every 10 --validate-frames 12");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("at 10x10+12x12 against Newton"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("validation references: 4 solved, 0 cached"), std::string::npos) << r.output;
  const auto rows = validation_rows(dir);
  ASSERT_EQ(rows.size(), 2u) << read_text(dir / "validation.csv");
  EXPECT_EQ(rows[1].rfind("10,10+12,xyz_v4+rot_h1,12,fnopt-ss,10,", 0), 0u) << rows[1];
  // The score column is the geometric mean of the last column's two grid means.
  std::vector<std::string> fields;
  std::istringstream row(rows[1]);
  for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
  ASSERT_EQ(fields.size(), 10u) << rows[1];
  const auto plus = fields[9].find('+');
  ASSERT_NE(plus, std::string::npos) << rows[1];
  const double coarse = std::stod(fields[9].substr(0, plus)), fine = std::stod(fields[9].substr(plus + 1));
  EXPECT_NEAR(std::stod(fields[6]), std::sqrt(coarse * fine), 1e-5 * std::stod(fields[6])) << rows[1];
  for (const std::string label :
       {"validation_10_xyz_v4_", "validation_12_xyz_v4_", "validation_10_rot_h1_", "validation_12_rot_h1_"})
    EXPECT_EQ(reference_files(dir, label), 1) << label;
  EXPECT_NE(r.output.find("at 10x10+12x12 (xyz_v4+rot_h1)"), std::string::npos) << r.output;
}

TEST(TrainCli, AResumedRunValidatesAsTheStraightRun) {
  const fnopt::testing::TempDir tmp;
  const auto straight = tmp.path() / "straight", resumed = tmp.path() / "resumed";
  ASSERT_EQ(run_fnopt("train --out " + straight.string() + " --steps 30" + kTinyRun).status, 0);
  ASSERT_EQ(run_fnopt("train --out " + resumed.string() + " --steps 20" + kTinyRun).status, 0);
  const CommandResult r = run_fnopt("train --out " + resumed.string() + " --steps 30 --resume" + kTinyRun);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("validation references: 0 solved, 2 cached"), std::string::npos) << r.output;
  EXPECT_EQ(validation_rows(resumed), validation_rows(straight));
  const auto best_line = [](const std::string& output) { return output.substr(output.find("best validation: step ")); };
  const CommandResult s = run_fnopt("train --out " + straight.string() + " --steps 30 --resume" + kTinyRun);
  EXPECT_EQ(best_line(r.output).substr(0, 40), best_line(s.output).substr(0, 40));
}

TEST(TrainCli, BadValidationFlagsAreOneLineErrors) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  for (const std::string flags :
       {" --validate-res 12 --validate-motions xy_v2,sideways", " --validate-res 12 --validate-frames 0",
        " --validate-res 2", " --validate-res 12,2", " --validate-res 12 --validate-every 0",
        " --validate-res 12 --validate-subspace 9", " --validate-res 12 --validate-handles corner,sideways",
        " --validate-res 12 --validate-motions rot_h1 --validate-handles single-center"}) {
    const CommandResult r = run_fnopt("train --out " + dir.string() + " --steps 5" + kTinyModel + flags);
    EXPECT_NE(r.status, 0) << flags;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << flags << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir)) << flags << ": nothing is written before the flags are checked";
    EXPECT_NE(r.output.find("validate"), std::string::npos) << flags << ": " << r.output;
    // A bad motion or preset (or a pair of them that makes no scene) names the flag that set it.
    if (flags.find("--validate-handles") != std::string::npos) {
      EXPECT_NE(r.output.find("validate-handles: "), std::string::npos) << flags << ": " << r.output;
    } else if (flags.find("--validate-motions") != std::string::npos) {
      EXPECT_NE(r.output.find("validate-motions: "), std::string::npos) << flags << ": " << r.output;
    }
  }
}

TEST(TrainCli, PoolRangesAreSetByFlagAndPrinted) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  for (const std::string flags : {" --range stretch=150", " --range speed=1:2", " --range shear=200:0.5",
                                  " --undamped-share 2", " --subspace 9", " --subspace -1", " --score subspace-step"}) {
    const CommandResult r = run_fnopt("train --out " + dir.string() + " --steps 2" + kTinyModel + flags);
    EXPECT_NE(r.status, 0) << flags;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << flags << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir)) << flags << ": nothing is written before the flags are checked";
  }
  const CommandResult r = run_fnopt("train --out " + dir.string() + " --steps 2" + kTinyModel +
                                    " --range stretch=150:8000 --range shear=0.5:200 --undamped-share 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("stretch 150:8000, shear 0.5:200, bend 0.005:20"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("undamped share 1"), std::string::npos) << r.output;
}

TEST(TrainCli, AnOutThatIsAFileIsAOneLineError) {
  const fnopt::testing::TempDir tmp;
  const std::string file = tmp.write("file", "not a folder\n");
  const CommandResult r = run_fnopt("train --out " + file + " --steps 2" + kTinyModel);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
  EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
}

TEST(TrainCli, ValidationFlagsWithoutValidateResAreRejected) {
  const fnopt::testing::TempDir tmp;
  const CommandResult r =
      run_fnopt("train --out " + (tmp.path() / "out").string() + " --steps 2 --validate-motions rot_h0");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--validate-motions requires --validate-res"), std::string::npos) << r.output;
}

TEST(TrainCli, TheSubspaceRuleTrainsAndValidatesAsChosen) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult r = run_fnopt("train --out " + dir.string() +
                                    " --steps 10 --subspace 4 --score subspace-step --validate-subspace 0" + kTinyRun);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the pool takes each proposal as fnopt-ss does: subspace step over the last 4 proposals"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("the loss scores each update where the rule ends, past the subspace step"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("validation every 10 steps: fnopt-ls N=10"), std::string::npos) << r.output;
  const auto rows = validation_rows(dir);
  ASSERT_EQ(rows.size(), 2u) << read_text(dir / "validation.csv");
  EXPECT_EQ(rows[1].rfind("10,12,xy_v2+rot_h0,12,fnopt-ls,10,", 0), 0u) << rows[1];
}

TEST(TrainCli, ThePqnDirectionTrainsAndValidatesWithFnoptSsPqn) {
  const fnopt::testing::TempDir tmp;
  const auto dir = tmp.path() / "out";
  const CommandResult alone = run_fnopt("train --out " + dir.string() + " --steps 10 --pqn-direction" + kTinyRun);
  EXPECT_NE(alone.status, 0);
  EXPECT_NE(alone.output.find("error: pqn-direction: needs a pool that takes the subspace step"), std::string::npos)
      << alone.output;
  const CommandResult r = run_fnopt("train --out " + dir.string() +
                                    " --steps 10 --subspace 4 --score subspace-step --pqn-direction" + kTinyRun);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("the pool takes each proposal as fnopt does: pqn's direction -A^-1 g, then the "
                          "subspace step over the last 4 directions"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("validation every 10 steps: fnopt N=10"), std::string::npos) << r.output;
  const auto rows = validation_rows(dir);
  ASSERT_EQ(rows.size(), 2u) << read_text(dir / "validation.csv");
  EXPECT_EQ(rows[1].rfind("10,12,xy_v2+rot_h0,12,fnopt,10,", 0), 0u) << rows[1];
}

TEST(TrainCli, TheProbeObjectiveStartsFromAModelAndLogsPqnAlone) {
  const fnopt::testing::TempDir tmp;
  const auto first = tmp.path() / "first", probe = tmp.path() / "probe";
  ASSERT_EQ(run_fnopt("train --out " + first.string() + " --steps 2" + kTinyModel).status, 0);
  const std::string init = " --objective probe --init " + (first / "model.pt").string();
  // The shape is the initial model's: the shape flags of kTinyModel are not needed.
  const CommandResult r =
      run_fnopt("train --out " + probe.string() +
                " --steps 4 --res 8 --envs 4 --batch 2 --threads 1 --probe-iterations 3 --probe-surface energy" + init);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("objective probe"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scored after 3 pqn iterations on the step's energy"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("starting from the weights of " + (first / "model.pt").string()), std::string::npos)
      << r.output;
  EXPECT_TRUE(std::filesystem::exists(probe / "model.pt"));
  std::istringstream log(read_text(probe / "train_log.csv"));
  std::string line;
  std::getline(log, line);
  EXPECT_EQ(line.substr(line.rfind(',') + 1), "ratio_without_probe");
  int rows = 0;
  while (std::getline(log, line)) {
    ++rows;
    EXPECT_GT(std::stod(line.substr(line.rfind(',') + 1)), 0.0) << line;
  }
  EXPECT_EQ(rows, 4);

  for (const auto& [arguments, error] : std::vector<std::pair<std::string, std::string>>{
           {init + " --validate-res 12", "validate-res: validates fnopt-ss rollouts, not a probe"},
           {" --probe-iterations 3", "probe_iterations: applies to the probe objective only"},
           {" --probe-surface energy", "probe_surface: applies to the probe objective only"},
           {init + " --probe-iterations 0", "probe.iterations: must lie in [1, 100]"},
           {" --init " + (tmp.path() / "missing.pt").string(), (tmp.path() / "missing.pt").string()}}) {
    const CommandResult bad = run_fnopt("train --out " + (tmp.path() / "bad").string() + " --steps 2" + arguments);
    EXPECT_EQ(bad.status, 2) << arguments << "\n" << bad.output;
    EXPECT_NE(bad.output.find(error), std::string::npos) << arguments << "\n" << bad.output;
    EXPECT_EQ(bad.output.find('\n'), bad.output.size() - 1) << bad.output;
  }
}

}  // namespace
