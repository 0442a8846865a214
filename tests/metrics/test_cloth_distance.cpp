// min_cloth_distance: a flat cloth's h/sqrt(2), and a cloth folded over onto itself at a known gap
// (its two layers a straight fold apart) gives that gap, the smallest over the frames.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/metrics/cloth_distance.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {
namespace {

// A rows x cols cloth of spacing h in the plane z = 0, its columns after `fold` laid back over the
// first ones at height `gap`: column fold + 1 straight above column fold (the crease a vertical
// wall), column fold + 2 above column fold - 1, and so on.
Eigen::VectorXf folded(int rows, int cols, double h, int fold, double gap) {
  Eigen::VectorXf x(3 * rows * cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const bool over = j > fold;
      x.segment<3>(3 * (i * cols + j)) = Vec3(over ? (2 * fold + 1 - j) * h : j * h, i * h, over ? gap : 0.0).cast<float>();
    }
  return x;
}

TEST(ClothDistance, AFlatClothsIsHOverRootTwo) {
  TrajectoryFrames frames;
  frames.rows = 6;
  frames.cols = 7;
  frames.positions = {folded(6, 7, 0.1, 100, 0.0)};
  EXPECT_NEAR(min_cloth_distance(frames), 0.1 / std::sqrt(2.0), 1e-7);
}

TEST(ClothDistance, TheLayersOfAFoldAreTheirGapApartAndTheSmallestFrameCounts) {
  TrajectoryFrames frames;
  frames.rows = 8;
  frames.cols = 12;
  frames.positions = {folded(8, 12, 0.1, 100, 0.0), folded(8, 12, 0.1, 5, 0.004), folded(8, 12, 0.1, 5, 0.02)};
  // The layers of frame 1 are 4 mm apart; the pairs at the crease's wall (vertical, one cell deep)
  // come a little closer, the vertex at its foot and the wall's diagonals within 0.2 % of the gap.
  const double smallest = min_cloth_distance(frames);
  EXPECT_LE(smallest, 0.004 + 1e-7);
  EXPECT_GT(smallest, 0.998 * 0.004);
  // Without it, the 2 cm frame's, whose wall (a fifth of a cell high) holds pairs a few % closer.
  frames.positions.erase(frames.positions.begin() + 1);
  EXPECT_LE(min_cloth_distance(frames), 0.02 + 1e-7);
  EXPECT_GT(min_cloth_distance(frames), 0.95 * 0.02);
}

}  // namespace
}  // namespace fnopt
