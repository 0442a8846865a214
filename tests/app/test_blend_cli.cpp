// fnopt blend-models as a user runs it: the blend is written and runs in simulate, and bad input is a
// one-line error (the blend's parameters: tests/fno/weight_blend_test.cpp).
#include <gtest/gtest.h>

#include "run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

const std::string kShipped = std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt";

TEST(BlendCli, WritesTheBlendAndItRuns) {
  const fnopt::testing::TempDir tmp;
  const std::string same = (tmp.path() / "same.pt").string();
  const CommandResult r = run_fnopt("blend-models " + kShipped + " " + kShipped + " --weight 0.3 --out " + same);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + same), std::string::npos) << r.output;
  const CommandResult run = run_fnopt("simulate --res 12 --frames 3 --optimizer fnopt-ss --model " + same + " --out " +
                                      (tmp.path() / "rollout.h5").string());
  EXPECT_EQ(run.status, 0) << run.output;
}

TEST(BlendCli, BadInputIsAOneLineError) {
  const fnopt::testing::TempDir tmp;
  const std::string out = (tmp.path() / "blend.pt").string();
  for (const std::string& arguments :
       {kShipped + " " + kShipped + " --weight 1.5 --out " + out, kShipped + " missing.pt --out " + out}) {
    const CommandResult r = run_fnopt("blend-models " + arguments);
    EXPECT_NE(r.status, 0) << arguments;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << arguments << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << arguments;
  }
  EXPECT_NE(run_fnopt("blend-models " + kShipped + " missing.pt --out " + out).output.find("missing.pt"),
            std::string::npos);
}

}  // namespace
