// The command line under mpirun with two ranks, as docs/cluster.md runs it: training and the sweeps
// give what one process gives, and a bad flag stops both ranks with one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <fnopt/util/parse_text.hpp>
#include "tests/app/run_fnopt.hpp"

namespace {

namespace fs = std::filesystem;

CommandResult run_two_ranks(const std::string& arguments) {
  return run_shell(
      std::string("env OMP_WAIT_POLICY=PASSIVE OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") +
      FNOPT_MPIEXEC + " -n 2 --oversubscribe " + FNOPT_BINARY + " " + arguments);
}

fs::path fresh_directory(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A CSV's rows split into cells, without the named columns (the timings, which differ run to run).
std::vector<std::vector<std::string>> table_without(const fs::path& csv, const std::vector<std::string>& dropped) {
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> keep;
  const std::string text = read_text(csv);
  for (std::string_view line : fnopt::split(text, '\n')) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    for (std::string_view cell : fnopt::split(line, ',')) cells.emplace_back(cell);
    if (keep.empty())
      for (const std::string& name : cells)
        keep.push_back(std::find(dropped.begin(), dropped.end(), name) == dropped.end());
    std::vector<std::string> kept;
    for (std::size_t i = 0; i < cells.size() && i < keep.size(); ++i)
      if (keep[i]) kept.push_back(cells[i]);
    rows.push_back(kept);
  }
  return rows;
}

const std::string kTinyTraining =
    " --res 8 --envs 8 --batch 4 --width 4 --layers 2 --modes 4 --lifting 8 --projection 4 --checkpoint-every 5";

TEST(MpiCli, TwoRankTrainingMatchesOneProcessAndResumes) {
  const fs::path dir = fresh_directory("fnopt_test_mpi_train");
  const CommandResult two = run_two_ranks("train --out " + (dir / "two").string() + " --steps 20" + kTinyTraining);
  ASSERT_EQ(two.status, 0) << two.output;
  EXPECT_NE(two.output.find("in each of 2 processes"), std::string::npos) << two.output;
  for (const char* file : {"model.pt", "checkpoint.pt", "train_log.csv"})
    EXPECT_TRUE(fs::exists(dir / "two" / file)) << file;
  const CommandResult one = run_fnopt("train --out " + (dir / "one").string() + " --steps 20" + kTinyTraining);
  ASSERT_EQ(one.status, 0) << one.output;
  // The same 20 steps: every step's loss and ratio agree to the float sums' order.
  const auto log_two = table_without(dir / "two" / "train_log.csv", {"seconds"});
  const auto log_one = table_without(dir / "one" / "train_log.csv", {"seconds"});
  ASSERT_EQ(log_two.size(), 21u);
  ASSERT_EQ(log_one.size(), 21u);
  for (std::size_t row = 1; row < log_one.size(); ++row)
    for (int column : {1, 3}) {  // loss, mean_ratio
      const double a = std::stod(log_one[row][column]), b = std::stod(log_two[row][column]);
      EXPECT_NEAR(a, b, 1e-4 * std::abs(a)) << "step " << row << " column " << column;
    }
  // --resume under mpirun continues the two ranks' checkpoint.
  const CommandResult resumed =
      run_two_ranks("train --out " + (dir / "two").string() + " --steps 25 --resume" + kTinyTraining);
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("at step 20"), std::string::npos) << resumed.output;
  EXPECT_EQ(table_without(dir / "two" / "train_log.csv", {}).size(), 26u);
  fs::remove_all(dir);
}

TEST(MpiCli, TwoRankCompareWritesTheRowsOfOneProcess) {
  const fs::path dir = fresh_directory("fnopt_test_mpi_compare");
  const std::string flags =
      " --res 8 --motions xy_v2,rot_h0 --frames 12 --optimizers pqn,newton,gd --iters-for pqn=5,10 "
      "--iters-for gd=20 --threads 1";
  const CommandResult two = run_two_ranks("compare --out " + (dir / "two").string() + flags);
  ASSERT_EQ(two.status, 0) << two.output;
  EXPECT_NE(two.output.find("2 processes"), std::string::npos) << two.output;
  const CommandResult one = run_fnopt("compare --out " + (dir / "one").string() + flags);
  ASSERT_EQ(one.status, 0) << one.output;
  // Same rows in the same order; the frontier column depends on the timings too.
  const std::vector<std::string> timings = {"ms_per_frame", "cpu_share", "ms_per_frame_cpu", "frontier"};
  const auto rows = table_without(dir / "two" / "compare.csv", timings);
  EXPECT_EQ(rows.size(), 1u + 2 * 4);  // header, 2 motions x (pqn 5, pqn 10, newton, gd 20)
  EXPECT_EQ(rows, table_without(dir / "one" / "compare.csv", timings));
  EXPECT_TRUE(fs::exists(dir / "two" / "compare.svg"));
  EXPECT_TRUE(fs::exists(dir / "two" / "report.md"));
  // Each Newton reference once, shared by the ranks.
  int references = 0;
  for (const auto& entry : fs::directory_iterator(dir / "two"))
    references += entry.path().filename().string().rfind("newton_reference_", 0) == 0;
  EXPECT_EQ(references, 2);
  // --resume under mpirun runs nothing again.
  const CommandResult again = run_two_ranks("compare --out " + (dir / "two").string() + flags + " --resume");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(table_without(dir / "two" / "compare.csv", timings), rows);
  fs::remove_all(dir);
}

TEST(MpiCli, TwoRankStabilityWritesTheRowsOfOneProcess) {
  const fs::path dir = fresh_directory("fnopt_test_mpi_stability");
  const std::string flags =
      " --res 8 --frames 10 --optimizers newton,pqn,gd --iters-for gd=20 --cases baseline,stretch-x100,speed-x4";
  const CommandResult two = run_two_ranks("stability --out " + (dir / "two").string() + flags);
  ASSERT_EQ(two.status, 0) << two.output;
  const CommandResult one = run_fnopt("stability --out " + (dir / "one").string() + flags);
  ASSERT_EQ(one.status, 0) << one.output;
  const auto rows = table_without(dir / "two" / "stability.csv", {"ms_per_frame"});
  EXPECT_EQ(rows.size(), 1u + 3 * 3);
  EXPECT_EQ(rows, table_without(dir / "one" / "stability.csv", {"ms_per_frame"}));
  fs::remove_all(dir);
}

TEST(MpiCli, ABadFlagStopsBothRanksWithOneLine) {
  const fs::path dir = fresh_directory("fnopt_test_mpi_bad");
  const CommandResult r = run_two_ranks("train --out " + dir.string() + " --steps 0");
  EXPECT_NE(r.status, 0);
  std::size_t lines = 0;
  for (std::size_t at = r.output.find("fnopt: error"); at != std::string::npos;
       at = r.output.find("fnopt: error", at + 1))
    ++lines;
  EXPECT_EQ(lines, 1u) << r.output;
  EXPECT_NE(r.output.find("steps: must be positive"), std::string::npos) << r.output;
  // An odd batch over two ranks is refused before any step, naming the flag.
  const CommandResult odd = run_two_ranks("train --out " + dir.string() + " --steps 2 --batch 3");
  EXPECT_NE(odd.status, 0);
  EXPECT_NE(odd.output.find("batch: must be a multiple of the processes (2)"), std::string::npos) << odd.output;
  EXPECT_FALSE(fs::exists(dir / "checkpoint.pt"));
  fs::remove_all(dir);
}

}  // namespace
