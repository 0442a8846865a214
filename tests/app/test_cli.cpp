// The fnopt command as a user runs it: bad input gives one line naming the problem and exit
// status 2; a small simulation writes a rollout file.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <tuple>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/parse_text.hpp>
#include "tests/app/run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

void expect_rejected(const std::string& arguments, const std::string& message) {
  const CommandResult r = run_fnopt(arguments);
  EXPECT_NE(r.status, 0) << arguments;
  EXPECT_NE(r.output.find(message), std::string::npos) << arguments << "\n" << r.output;
}

TEST(Cli, RejectsBadInputWithOneLineNamingTheProblem) {
  expect_rejected("simulate --res 2 --frames 1", "res: ");
  expect_rejected("simulate --rows 2 --frames 1", "rows: ");
  expect_rejected("simulate --frames 0", "frames");
  expect_rejected("simulate --handles nowhere --frames 1", "handles");
  expect_rejected("simulate --motion sideways --frames 1", "motion");
  expect_rejected("simulate --density -1 --frames 1", "density");
  expect_rejected("simulate --stretch nan --frames 1", "stretch");
  expect_rejected("simulate --handle-vertices 0,99 --res 8 --frames 1", "handle-vertices");
  expect_rejected("simulate --trajectory /nonexistent.csv --frames 1", "trajectory");
  expect_rejected("simulate --optimizer magic --frames 1", "optimizer");
  expect_rejected("simulate --tolerance 1e-8 --frames 1", "tolerance: applies to the methods that solve to a tolerance");
  const CommandResult r = run_fnopt("simulate --res 2 --frames 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

TEST(Cli, SimulateWritesARolloutAndSaysSo) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_cli";
  std::filesystem::create_directories(dir);
  const auto out = (dir / "r.h5").string();
  const CommandResult r =
      run_fnopt("simulate --optimizer newton --res 8 --frames 5 --out " + out + " --obj-dir " + (dir / "obj").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out));
  EXPECT_TRUE(std::filesystem::exists(dir / "obj" / "frame_0005.obj"));
  EXPECT_NE(r.output.find("5/5 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("5/5 steps converged"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

// bench newton prints the reference's table and, with --keep, writes the rollout it timed: the
// same Newton rollout simulate writes.
TEST(Cli, BenchNewtonKeepsTheRolloutItTimed) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_cli_bench";
  std::filesystem::create_directories(dir);
  const CommandResult r = run_fnopt("bench newton --res 8 --frames 4 --threads 1 --keep " + dir.string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("residual acceleration <= 0.1 m/s^2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("4/4"), std::string::npos) << r.output;
  const auto kept = (dir / "newton_8.h5").string();
  ASSERT_TRUE(std::filesystem::exists(kept));
  const auto simulated = (dir / "simulated.h5").string();
  ASSERT_EQ(run_fnopt("simulate --optimizer newton --res 8 --frames 4 --threads 1 --out " + simulated).status, 0);
  const fnopt::TrajectoryFrames a = fnopt::read_trajectory_frames(kept), b = fnopt::read_trajectory_frames(simulated);
  ASSERT_EQ(a.positions.size(), 5u);
  ASSERT_EQ(b.positions.size(), a.positions.size());
  for (std::size_t f = 0; f < a.positions.size(); ++f) EXPECT_EQ(a.positions[f], b.positions[f]) << f;
  EXPECT_NE(fnopt::read_rollout_provenance(kept).optimizer_settings.find("trust-region"), std::string::npos);
  // The multigrid at every grid (the reference's own from about 82^2) converges the same steps.
  const CommandResult multigrid = run_fnopt("bench newton --res 8 --frames 4 --threads 1 --preconditioner multigrid");
  EXPECT_EQ(multigrid.status, 0) << multigrid.output;
  EXPECT_NE(multigrid.output.find("preconditioner multigrid"), std::string::npos) << multigrid.output;
  EXPECT_NE(multigrid.output.find("4/4"), std::string::npos) << multigrid.output;
  const CommandResult missing = run_fnopt("bench newton --res 8 --frames 1 --keep " + (dir / "nope").string());
  EXPECT_EQ(missing.status, 2) << missing.output;
  std::filesystem::remove_all(dir);
}

// bench speed: each method with 1 and 2 threads, each in a process of its own, its evaluations and
// peak memory; Newton converges every step; 1.0's figures exist only for 32^2, 64^2 and 100^2.
TEST(Cli, BenchSpeedRunsEachMethodWithOneAndTwoThreads) {
  const CommandResult r = run_fnopt("bench speed --res 6 --frames 4");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("each run in a process of its own"), std::string::npos) << r.output;
  const std::regex row(R"(\n +6\^2 +(pqn 10|fnopt 10|newton) +([12]) +([0-9.]+) +- +- +(\S+) +([0-9.]+) +([0-9.]+) +([0-9]+) +(\d+)/(\d+))");
  std::map<std::string, int> rows;
  for (auto m = std::sregex_iterator(r.output.begin(), r.output.end(), row); m != std::sregex_iterator(); ++m) {
    const auto& match = *m;
    ++rows[match[1]];
    EXPECT_GT(std::stod(match[3]), 0.0) << match[0];
    EXPECT_EQ(match[4] == "-", match[2] == "1") << match[0];  // a speed-up on the 2-thread row only
    EXPECT_GE(std::stod(match[5]), std::stod(match[6])) << match[0];  // evaluations >= gradients >= 1
    EXPECT_GE(std::stod(match[6]), 1.0) << match[0];
    EXPECT_GT(std::stoi(match[7]), 0) << match[0];
    EXPECT_EQ(match[9], "4") << match[0];
    if (match[1] == "newton") {
      EXPECT_EQ(match[8], "4") << match[0];
    }
  }
  EXPECT_EQ(rows["pqn 10"], 2) << r.output;
  EXPECT_EQ(rows["newton"], 2) << r.output;
  const CommandResult bad = run_fnopt("bench speed --res 6 --frames 2 --row pqn:x");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("row: expected METHOD or METHOD:ITERATIONS, got 'pqn:x'"), std::string::npos) << bad.output;
}

// bench kernels: a row per resolution and angle term, with the stencil count and a positive rate
// for scalar and each SIMD level the CPU has.
TEST(Cli, BenchKernelsPrintsStencilsPerSecondPerLevel) {
  const CommandResult r = run_fnopt("bench kernels --res 8,10 --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::size_t header = r.output.find("   res   term  stencils    scalar");
  ASSERT_NE(header, std::string::npos) << r.output;
  const std::string header_line = r.output.substr(header, r.output.find('\n', header) - header);
  std::istringstream header_cells(header_line);
  int columns = 0;
  for (std::string cell; header_cells >> cell;) ++columns;
  ASSERT_GE(columns, 5) << header_line;  // res, term, stencils, scalar, ..., speed-up
  // n^2 cloth: 4 (n-1)^2 shear corners, 2 n (n-2) bend hinges.
  for (const auto& [n, term, stencils] : {std::tuple{8, "shear", 196}, std::tuple{8, "bend", 96},
                                          std::tuple{10, "shear", 324}, std::tuple{10, "bend", 160}}) {
    const std::string row_start = (n < 10 ? "   " : "  ") + std::to_string(n) + "^2 " +
                                  std::string(std::strlen(term) == 5 ? " " : "  ") + term;
    const std::size_t at = r.output.find(row_start);
    ASSERT_NE(at, std::string::npos) << row_start << "\n" << r.output;
    std::istringstream cells(r.output.substr(at, r.output.find('\n', at) - at));
    std::string grid, name;
    long count = 0;
    cells >> grid >> name >> count;
    EXPECT_EQ(count, stencils) << grid << " " << name;
    int rates = 0;
    for (double rate; cells >> rate; ++rates) EXPECT_GT(rate, 0.0) << grid << " " << name;
    EXPECT_EQ(rates, columns - 3) << grid << " " << name;
  }
}

// With --repeat the table gives each resolution's median over the runs and the range of ms/frame; on one
// thread every run does the same work, so no row says otherwise.
TEST(Cli, BenchNewtonRepeatsInRoundsAndGivesTheRange) {
  const CommandResult r = run_fnopt("bench newton --res 8,9 --frames 4 --threads 1 --repeat 3");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("3 runs per resolution, in rounds"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("range"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(3/3)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("did different work"), std::string::npos) << r.output;
  // The rounds: 8, 9, 8, 9, 8, 9.
  const std::size_t second_eight = r.output.find("bench 8^2 (2/3)"), first_nine = r.output.find("bench 9^2 (1/3)");
  ASSERT_NE(second_eight, std::string::npos) << r.output;
  ASSERT_NE(first_nine, std::string::npos) << r.output;
  EXPECT_LT(first_nine, second_eight);
  for (const char* row : {"   8^2 ", "   9^2 "}) {
    const std::size_t at = r.output.find(row);
    ASSERT_NE(at, std::string::npos) << row << r.output;
    EXPECT_NE(r.output.find("4/4", at), std::string::npos) << row << r.output;
  }
}

TEST(Cli, SimulateRunsPqnByDefaultAndTheShippedModelOneFlagAway) {
  const fnopt::testing::TempDir tmp;
  const auto out = (tmp.path() / "default.h5").string();
  const CommandResult r = run_fnopt("simulate --res 16 --frames 10 --out " + out);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("pqn: history=5 (H0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("pqn: 10/10 frames"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("10.00 iterations/step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("finite"), std::string::npos) << r.output;
  const CommandResult learned = run_fnopt("simulate --res 16 --frames 10 --optimizer fnopt-ss --out " + out);
  EXPECT_EQ(learned.status, 0) << learned.output;
  EXPECT_NE(learned.output.find("fnopt-ss: 10/10 frames"), std::string::npos) << learned.output;
  EXPECT_NE(learned.output.find("subspace=8 carried"), std::string::npos) << learned.output;
  // fnopt-pqn at 40^2: the FNO runs on the 32-vertex coarse grid.
  const CommandResult probed = run_fnopt("simulate --res 40 --frames 6 --optimizer fnopt-pqn --out " + out);
  EXPECT_EQ(probed.status, 0) << probed.output;
  EXPECT_NE(probed.output.find("fnopt-pqn: 6/6 frames"), std::string::npos) << probed.output;
  EXPECT_NE(probed.output.find("proposal grid=32"), std::string::npos) << probed.output;
  EXPECT_NE(probed.output.find("finite"), std::string::npos) << probed.output;
}

// Two processes, same scene and model, must write the same rollout to the bit: a comparison
// of optimizers is only honest if rerunning it gives the same numbers. With FFTW_MEASURE the
// plans (and so the FNO's float round-off) were chosen by timing: two 150-frame fnopt-ls runs
// at 64^2 ended e_3D 0.9e-2 apart.
TEST(Cli, SimulateIsReproducibleAcrossProcesses) {
  const fnopt::testing::TempDir tmp;
  std::vector<fnopt::TrajectoryFrames> runs;
  for (const char* name : {"a.h5", "b.h5"}) {
    const auto path = (tmp.path() / name).string();
    const CommandResult r = run_fnopt("simulate --res 64 --frames 12 --threads 1 --optimizer fnopt-ss --out " + path);
    ASSERT_EQ(r.status, 0) << r.output;
    runs.push_back(fnopt::read_trajectory_frames(path));
  }
  ASSERT_EQ(runs[0].positions.size(), runs[1].positions.size());
  for (std::size_t f = 0; f < runs[0].positions.size(); ++f)
    EXPECT_TRUE(runs[0].positions[f] == runs[1].positions[f]) << "frame " << f << " differs";
}

// One default for every subcommand: $OMP_NUM_THREADS where it is set, else one thread (OpenMP's
// spinning threads made a 2-thread default many times slower beside one other job on 2 cores;
// docs/design.md §9). Loading a
// model initialises LibTorch, which resets OpenMP's count: the learned optimizer is the case to
// check.
TEST(Cli, ThreadsDefaultToOmpNumThreadsOrOne) {
  const fnopt::testing::TempDir tmp;
  const auto path = (tmp.path() / "t.h5").string();
  const CommandResult given =
      run_fnopt("simulate --res 8 --frames 1 --optimizer fnopt-ss --out " + path, "OMP_NUM_THREADS=3");
  ASSERT_EQ(given.status, 0) << given.output;
  EXPECT_NE(given.output.find(", 3 threads"), std::string::npos) << given.output;
  const CommandResult unset =
      run_fnopt("simulate --res 8 --frames 1 --optimizer fnopt-ss --out " + path, "-u OMP_NUM_THREADS");
  ASSERT_EQ(unset.status, 0) << unset.output;
  EXPECT_NE(unset.output.find(", 1 thread\n"), std::string::npos) << unset.output;
  const CommandResult compare = run_fnopt(
      "compare --res 8 --frames 2 --optimizers pqn --iters 2 --step-samples 1 "
      "--cd-samples 100 --out " +
          (tmp.path() / "c").string(),
      "-u OMP_NUM_THREADS");
  ASSERT_EQ(compare.status, 0) << compare.output;
  EXPECT_NE(compare.output.find("1 thread (fixed for every timing)"), std::string::npos) << compare.output;
}

TEST(Cli, EverySubcommandHasHelp) {
  for (const char* command : {"simulate", "train", "bench", "compare", "evaluate", "view"}) {
    const CommandResult r = run_fnopt(std::string(command) + " --help");
    EXPECT_EQ(r.status, 0) << command;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << command;
  }
  // Where help states the reference's stop, it is the one the reference uses.
  for (const char* command : {"simulate", "stability"}) {
    const CommandResult r = run_fnopt(std::string(command) + " --help");
    EXPECT_NE(
        r.output.find("residual acceleration of " +
                      fnopt::number_text(fnopt::NewtonOptimizer::reference_solve_options().acceleration_tolerance) +
                      " m/s^2"),
        std::string::npos)
        << r.output;
  }
}

// The scene flags are the scene key table's command-line keys, each with its help.
TEST(Cli, SceneFlagsAreTheKeysOfTheSceneKeyTable) {
  const CommandResult r = run_fnopt("simulate --help");
  ASSERT_EQ(r.status, 0) << r.output;
  for (const fnopt::SceneKey& key : fnopt::scene_keys()) {
    if (!key.accepted_by(fnopt::kCommandLine)) continue;
    EXPECT_NE(r.output.find("--" + std::string(key.name) + " "), std::string::npos) << key.name;
    if (key.type == fnopt::SceneKeyType::Switch) {
      EXPECT_NE(r.output.find("--no-" + std::string(key.name)), std::string::npos) << key.name;
    }
  }
}

}  // namespace
