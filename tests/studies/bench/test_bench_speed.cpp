// fnopt bench speed's parts in-process: a row's measurement counts the objective's evaluations and
// reports every step converged for Newton; its line round-trips; the recorded 1.0 figures read, and
// a malformed baseline or row is refused by name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <fnopt/studies/bench/bench_speed.hpp>
#include <fnopt/util/installed_data.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

BenchRun tiny_run() {
  BenchRun run;
  run.resolutions = {6};
  run.frames = 4;
  return run;
}

TEST(BenchSpeed, ARowCountsTheObjectivesEvaluationsPerFrame) {
  const SpeedMeasurement pqn = measure_speed(tiny_run(), "pqn:3");
  EXPECT_EQ(pqn.steps, 4);
  EXPECT_GT(pqn.ms_per_frame, 0.0);
  EXPECT_GT(pqn.peak_mb, 0.0);
  // Each of the 3 iterations needs the gradient at its iterate; line-search trials add evaluations.
  EXPECT_GE(pqn.gradients_per_frame, 3.0);
  EXPECT_GE(pqn.evaluations_per_frame, pqn.gradients_per_frame);
  const SpeedMeasurement more = measure_speed(tiny_run(), "pqn:6");
  EXPECT_GT(more.gradients_per_frame, pqn.gradients_per_frame);
  const SpeedMeasurement newton = measure_speed(tiny_run(), "newton");
  EXPECT_EQ(newton.converged, newton.steps);
  EXPECT_GE(newton.gradients_per_frame, 1.0);
}

TEST(BenchSpeed, TheSpeedLineRoundTrips) {
  SpeedMeasurement m;
  m.ms_per_frame = 12.345678;
  m.evaluations_per_frame = 17.25;
  m.gradients_per_frame = 11.5;
  m.peak_mb = 812.0;
  m.converged = 389;
  m.steps = 389;
  SpeedMeasurement back;
  ASSERT_TRUE(parse_speed_line(speed_line(m), back));
  EXPECT_DOUBLE_EQ(back.ms_per_frame, m.ms_per_frame);
  EXPECT_DOUBLE_EQ(back.evaluations_per_frame, m.evaluations_per_frame);
  EXPECT_DOUBLE_EQ(back.gradients_per_frame, m.gradients_per_frame);
  EXPECT_DOUBLE_EQ(back.peak_mb, m.peak_mb);
  EXPECT_EQ(back.converged, 389);
  EXPECT_FALSE(parse_speed_line("fnopt bench: progress 3/4", back));
}

TEST(BenchSpeed, ReadsTheRecordedFiguresAndRefusesAMalformedOne) {
  const auto rows = read_speed_baseline(installed_data_path("bench/speed-1.0.csv", "src/fnopt/studies/bench/speed-1.0.csv"));
  ASSERT_EQ(rows.size(), 9u);
  for (const SpeedBaseline& b : rows) {
    EXPECT_TRUE(b.res == 32 || b.res == 64 || b.res == 100) << b.res;
    EXPECT_EQ(b.threads, 1);
    EXPECT_GT(b.ms_per_frame, 0.0);
  }
  const auto path = std::filesystem::temp_directory_path() / "fnopt_test_speed_baseline.csv";
  std::ofstream(path) << "res,threads,method,ms_per_frame,source\n32,1,pqn 10,4.2,a run\n64,one,pqn 10,18,a run\n";
  EXPECT_TRUE(testing::throws_error([&] { read_speed_baseline(path.string()); },
                                    "baseline: " + path.string() + ":3: expected res,threads,method,ms_per_frame"));
  std::ofstream(path) << "threads,res,method,ms_per_frame\n1,32,pqn 10,4.2\n";
  EXPECT_TRUE(testing::throws_error([&] { read_speed_baseline(path.string()); },
                                    "baseline: " + path.string() + ": expected the columns res,threads,method,ms_per_frame"));
  std::filesystem::remove(path);
  EXPECT_TRUE(testing::throws_error([&] { measure_speed(tiny_run(), "pqn:0"); }, "row: expected METHOD"));
}

}  // namespace
}  // namespace fnopt
