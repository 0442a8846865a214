// fnopt fit-handles' run in-process: its flags' values checked by name, and a tiny fit to a hidden
// path's frame that writes the loss table and a trajectory the scene can replay.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <fnopt/fits/handle_path_fit_run.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

TEST(HandlePathFitRun, RefusesAnUnknownMethodOrBasisByName) {
  HandlePathFitRun run;
  run.basis = "bezier";
  EXPECT_TRUE(testing::throws_error([&] { run.validate(); }, "basis: expected spline or linear, got 'bezier'"));
  run.basis = "linear";
  run.method = "newton";
  EXPECT_TRUE(testing::throws_error([&] { run.validate(); }, "method: "));
  run.method = "both";
  run.validate();
  EXPECT_EQ(run.params.path.basis, HandlePathBasis::PiecewiseLinear);
  EXPECT_EQ(run.methods().size(), 2u);
}

TEST(HandlePathFitRun, FitsAHiddenPathAndWritesItsOutputs) {
  const testing::TempDir tmp;
  HandlePathFitRun run;
  run.method = "gradient";
  run.params.passes = 6;
  run.csv = (tmp.path() / "loss.csv").string();
  run.out = (tmp.path() / "path.csv").string();
  run.validate();
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 9;
  scene.speed = 4.0;
  ::testing::internal::CaptureStdout();
  run_handle_path_fit(run, resolve(scene));
  const std::string printed = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(printed.find("gradient loss"), std::string::npos) << printed;
  std::ifstream csv(run.csv);
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "method,passes,loss_m2");
  Scene replay = scene;
  replay.trajectory = run.out;
  EXPECT_NO_THROW(resolve(replay));
}

}  // namespace
}  // namespace fnopt
