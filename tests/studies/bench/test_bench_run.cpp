// fnopt bench's tables in-process: a Newton table on a tiny grid prints one row per resolution
// with every step converged; unknown tables and preconditioners are refused by name.
#include <gtest/gtest.h>

#include <regex>

#include <fnopt/studies/bench/bench_run.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

TEST(BenchRun, TheNewtonTablePrintsARowPerResolutionWithEveryStepConverged) {
  BenchRun run;
  run.resolutions = {6, 8};
  run.frames = 3;
  ::testing::internal::CaptureStdout();
  run_bench(run);
  const std::string table = ::testing::internal::GetCapturedStdout();
  EXPECT_NE(table.find("   6^2"), std::string::npos) << table;
  EXPECT_NE(table.find("   8^2"), std::string::npos) << table;
  EXPECT_EQ(table.find("different work"), std::string::npos) << table;
  // The last column: converged steps / steps.
  const std::regex converged(R"(\^2 .* (\d+)/(\d+)\n)");
  int rows = 0;
  for (auto match = std::sregex_iterator(table.begin(), table.end(), converged); match != std::sregex_iterator();
       ++match, ++rows)
    EXPECT_EQ((*match)[1], (*match)[2]) << table;
  EXPECT_EQ(rows, 2) << table;
}

TEST(BenchRun, RefusesAnUnknownTableOrPreconditionerByName) {
  BenchRun run;
  run.resolutions = {6};
  run.frames = 2;
  run.what = "speed-of-light";
  EXPECT_TRUE(testing::throws_error([&] { run_bench(run); }, "bench: unknown benchmark 'speed-of-light'"));
  run.what = "newton";
  run.preconditioner = "jacobi";
  EXPECT_TRUE(testing::throws_error([&] { run_bench(run); }, "preconditioner: expected auto, factor or multigrid"));
}

}  // namespace
}  // namespace fnopt
