// Frame time matching (docs/design.md §8): ARCSim's 1/30 s against fnopt's 1/60 s.
#include <gtest/gtest.h>

#include <vector>

#include <fnopt/metrics/frame_matching.hpp>

namespace fnopt {
namespace {

TEST(FrameMatching, PairsArcsimFramesWithEverySecondFnoptFrame) {
  std::vector<double> arcsim, fnopt;
  for (int k = 0; k < 196; ++k) arcsim.push_back(k / 30.0);
  for (int k = 0; k <= 390; ++k) fnopt.push_back(k * (1.0 / 60.0));
  const auto matches = match_frames(arcsim, fnopt);
  ASSERT_EQ(matches.size(), 196u);
  for (int k = 0; k < 196; ++k) {
    EXPECT_EQ(matches[k].reference, k);
    EXPECT_EQ(matches[k].rollout, 2 * k);
  }
  // A rollout that diverged after 100 steps: only the frames it has.
  fnopt.resize(101);
  EXPECT_EQ(match_frames(arcsim, fnopt).size(), 51u);
  // The same times match one to one; times must not decrease.
  EXPECT_EQ(match_frames(fnopt, fnopt).size(), fnopt.size());
  EXPECT_ANY_THROW(match_frames({0.0, 0.2, 0.1}, fnopt));
}

}  // namespace
}  // namespace fnopt
