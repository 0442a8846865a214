// The repulsion study in-process: one row per preset, repulsion off and on, and optimizer; a
// --resume keeps them and adds none.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include <fnopt/studies/repulsion/repulsion_study.hpp>
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(RepulsionStudy, RunsEveryPresetOffAndOnAndResumesWithoutRepeating) {
  const testing::TempDir tmp;
  RepulsionStudy study;
  study.base.rows = study.base.cols = 8;
  study.base.frames = 4;
  OptimizerChoice pqn;
  pqn.name = "pqn";
  pqn.iterations = 3;
  study.optimizers = {pqn};
  study.out = tmp.path().string();
  study.command_line = "fnopt repulsion-study (test)";
  run_repulsion_study(study);
  const std::string csv = read(tmp.path() / "repulsion.csv");
  const auto rows = std::count(csv.begin(), csv.end(), '\n') - 1;
  EXPECT_EQ(rows, static_cast<long>(2 * repulsion_presets().size())) << csv;
  for (const std::string& preset : repulsion_presets()) {
    EXPECT_NE(csv.find(preset + ",off,pqn"), std::string::npos) << csv;
    EXPECT_NE(csv.find(preset + ",on,pqn"), std::string::npos) << csv;
  }
  EXPECT_NE(read(tmp.path() / "report.md").find("fnopt repulsion-study (test)"), std::string::npos);
  study.resume = true;
  run_repulsion_study(study);
  EXPECT_EQ(read(tmp.path() / "repulsion.csv"), csv);
}

}  // namespace
}  // namespace fnopt
