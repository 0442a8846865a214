// Bad input, as a new user gives it, across the subcommands: every case exits with status 2 and
// one line that names the flag, file or key at fault, before any work (no output file appears).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/app/run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

struct BadInput {
  std::string arguments;  // {dir} stands for the test's directory
  std::string error;      // the error line's text after "fnopt: error: " starts with this
};

std::string with_dir(std::string text, const std::string& dir) {
  for (auto at = text.find("{dir}"); at != std::string::npos; at = text.find("{dir}")) text.replace(at, 5, dir);
  return text;
}

class BadInputTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fnopt::testing::TempDir();
    const fs::path d = dir_->path();
    std::ofstream(d / "dup.mat") << "stretch = 100\nstretch = 200\n";
    std::ofstream(d / "unknown.mat") << "bogus = 3\n";
    std::ofstream(d / "dup.scene") << "frames = 3\nframes = 4\n";
    std::ofstream(d / "unknown.scene") << "colour = red\n";
    std::ofstream(d / "binary.scene", std::ios::binary) << std::string("PK\x03\x04\x01\x02 bytes", 12);
    std::ofstream(d / "file") << "x";
    const CommandResult r = run_fnopt("simulate --res 8 --frames 3 --threads 1 --out " + (d / "ref.h5").string());
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static fnopt::testing::TempDir* dir_;
};

fnopt::testing::TempDir* BadInputTest::dir_ = nullptr;

const std::string S = "simulate --res 8 --frames 3 --threads 1 --out {dir}/never.h5 ";
const std::string E = "evaluate {dir}/ref.h5 --reference {dir}/ref.h5 --threads 1 ";

const std::vector<BadInput> kCases = {
    // The parser's own errors.
    {"simulate --bogus", "The following argument was not expected: --bogus"},
    {"simulate --res abc --out {dir}/never.h5", "res: expected an integer, got 'abc'"},
    {"compare --res 8", "--out is required"},
    {"simulate --res 8 --rows 6 --out {dir}/never.h5", "--res excludes --rows"},
    {"simulate --motion static --trajectory {dir}/file --out {dir}/never.h5", "--motion excludes --trajectory"},
    {"simulate --handles corner --handle-vertices 0,0 --out {dir}/never.h5", "--handles excludes --handle-vertices"},
    {S + "--scene {dir}/missing.scene", "--scene: File does not exist"},
    // Grids and scenes.
    {"simulate --res 100000 --out {dir}/never.h5", "res: a 100000x100000 grid"},
    {"simulate --res 46341 --out {dir}/never.h5", "res: a 46341x46341 grid"},
    {"simulate --res 2 --out {dir}/never.h5", "res: the grid needs at least 3 vertices"},
    {S + "--handle-vertices ''", "handle-vertices: is empty"},
    {S + "--handle-vertices 99,99", "handle-vertices"},
    {S + "--handles nope", "handles: unknown preset 'nope'"},
    {S + "--motion nope", "motion: unknown motion 'nope'"},
    {S + "--trajectory {dir}/missing.csv", "trajectory: {dir}/missing.csv: cannot open the file"},
    {S + "--dt 0", "dt: must be a positive finite time step"},
    {S + "--speed -1", "speed: must be a positive finite factor"},
    {S + "--size 0", "size: must be a positive finite length"},
    {S + "--gravity 1,2", "gravity: expected three numbers"},
    {S + "--stretch -1", "stretch: must be a positive finite number"},
    {S + "--damping -1", "damping: must be a non-negative finite number"},
    {S + "--repulsion-stiffness 0", "repulsion-stiffness: must be a positive finite number"},
    {S + "--scene {dir}/dup.scene", "{dir}/dup.scene:2: frames: given twice (first on line 1)"},
    {S + "--scene {dir}/unknown.scene", "{dir}/unknown.scene:1: colour: unknown setting"},
    {S + "--scene {dir}/binary.scene", "{dir}/binary.scene:1: not a text scene file"},
    {S + "--material {dir}/dup.mat", "{dir}/dup.mat:2: stretch: given twice (first on line 1)"},
    {S + "--material {dir}/unknown.mat", "{dir}/unknown.mat:1: bogus: unknown material key"},
    {S + "--material {dir}", "material: '{dir}' is a directory"},
    {S + "--material nope", "material: unknown preset or unreadable file 'nope'"},
    // Optimizers and models.
    {S + "--optimizer nope", "optimizer: unknown optimizer 'nope'"},
    {S + "--iters 0", "--iters: must be a positive iteration budget, got '0'"},
    {S + "--threads 0", "--threads: must lie in [1,"},
    {S + "--threads -1", "--threads: must lie in [1,"},
    {S + "--threads 1000", "--threads: must lie in [1,"},
    {S + "--optimizer fnopt-interp500", "optimizer: 'fnopt-interp500' solves on a grid with 500 vertices"},
    {S + "--pqn-history -1", "pqn-history: must lie in [0, 1000]"},
    {S + "--optimizer fnopt-ss --model {dir}/missing.pt", "{dir}/missing.pt: no such FNO weights file"},
    {S + "--optimizer fnopt-ss --model {dir}/dup.mat", "{dir}/dup.mat: not an fnopt FNO weights file"},
    {S + "--optimizer fnopt-pqn --model {dir}/missing.pt", "{dir}/missing.pt: no such FNO weights file"},
    {S + "--optimizer fnopt-pqn --pqn-history -1", "pqn-history: must lie in [0, 1000]"},
    // Output locations, checked before the work.
    {"simulate --res 8 --frames 3 --out /proc/fnopt.h5", "out: cannot write in '/proc'"},
    {"simulate --res 8 --frames 3 --out {dir}", "out: '{dir}' is a directory"},
    {"simulate --res 8 --frames 3 --out ''", "out: is empty"},
    {"simulate --res 8 --frames 3 --out {dir}/nodir/x.h5", "out: directory '{dir}/nodir' does not exist"},
    {S + "--obj-dir {dir}/file", "obj-dir: '{dir}/file' exists and is not a directory"},
    {"compare --res 8 --frames 2 --out {dir}/file", "out: '{dir}/file' exists and is not a directory"},
    {"fit-material --reference {dir}/ref.h5 --out {dir}", "out: '{dir}' is a directory"},
    // The other subcommands' own flags.
    {E + "--optimizer nope", "optimizer: unknown optimizer 'nope'"},
    {E + "--step-samples 0", "step-samples: must be at least 1"},
    {E + "--per-frame /proc/fnopt.csv", "per-frame: cannot write in '/proc'"},
    {"compare --res 8 --frames 2 --cd-stride 0 --out {dir}/c", "cd-stride: must be at least 1"},
    {"compare --res 8 --frames 2 --optimizers nope --out {dir}/c", "optimizer: unknown optimizer 'nope'"},
    {"stability --cases '' --out {dir}/s", "cases: is empty"},
    {"stability --cases nope --out {dir}/s", "cases: unknown case 'nope'"},
    {"train --out {dir}/t --resume", "resume: no checkpoint to resume"},
    {"train --out {dir}/t --minutes -1", "minutes: must be 0 (no limit) or a positive number"},
    {"train --out {dir}/t --layers 1", "layers: must be at least 2"},
    {"train --out {dir}/t --batch 0", "batch: must lie in [1, environments]"},
    {"train --out {dir}/t --range foo=1:2", "range: unknown quantity 'foo'"},
    {"train --out {dir}/t --validate-res 2", "validate-res: must be at least 3"},
    {"fit-material --reference {dir}/ref.h5 --cd-stride 0 --out {dir}/m.txt", "cd-stride: must be at least 1"},
    {"bench nope", "bench: unknown benchmark 'nope' (choose newton, fno, adjoint, contact, kernels, speed or all)"},
    {"bench newton --res 8 --preconditioner lu", "preconditioner: expected auto, factor or multigrid, got 'lu'"},
    {"bench newton --res 8 --repeat 0", "--repeat: Value 0 not in range 1 to 100"},
    // The viewer: every file checked before it serves.
    {"view {dir}/missing.h5", "{dir}/missing.h5: no such file"},
    {"view {dir}/file", "{dir}/file: not an HDF5 file"},
    {"view {dir}/ref.h5 --against {dir}/missing.h5", "{dir}/missing.h5: no such file"},
    {"view {dir}", "{dir}: no compare.csv"},
    {"view {dir}/ref.h5 --port 70000", "--port: Value 70000 not in range"},
};

TEST_F(BadInputTest, EveryCaseExitsWithStatusTwoAndOneLineNamingTheProblem) {
  ASSERT_GE(kCases.size(), 40u);
  const std::string dir = dir_->path().string();
  for (const BadInput& c : kCases) {
    const std::string arguments = with_dir(c.arguments, dir);
    const CommandResult r = run_fnopt(arguments);
    const std::string expected = "fnopt: error: " + with_dir(c.error, dir);
    EXPECT_EQ(r.status, 2) << arguments << "\n" << r.output;
    EXPECT_EQ(r.output.rfind(expected, 0), 0u) << arguments << "\nexpected: " << expected << "\ngot: " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << arguments << "\n" << r.output;
  }
  // Nothing was written on the way: no rollout, no training folder, no comparison.
  EXPECT_FALSE(fs::exists(dir_->path() / "never.h5"));
  EXPECT_FALSE(fs::exists(dir_->path() / "t" / "checkpoint.pt"));
  EXPECT_FALSE(fs::exists(dir_->path() / "c" / "compare.csv"));
}

// The rule behind the output checks: a run never does its work and then fails to save it.
TEST_F(BadInputTest, AnUnwritableOutputFailsBeforeTheFirstStep) {
  const auto start = std::chrono::steady_clock::now();
  const CommandResult r = run_fnopt("simulate --res 100 --out /proc/fnopt.h5");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output.find("simulate 1/"), std::string::npos) << "a step ran: " << r.output;
  std::printf("refused in %.2f s (the binary's start-up included)\n", seconds);
}

}  // namespace
