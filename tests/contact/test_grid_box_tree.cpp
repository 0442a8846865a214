// The hierarchy over a grid's cells (contact/grid_box_tree.hpp) against brute force over every pair
// of cells: the same overlapping pairs, each once, with and without a weight window, on boxes laid
// out like a cloth's quads (neighbours in (i, j) overlap) with some thrown far or folded back.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>
#include <vector>

#include <fnopt/contact/grid_box_tree.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

struct Cells {
  std::vector<Box> boxes;
  std::vector<double> weights;
};

// rows x cols boxes of side 1.2 at spacing 1 (each overlaps its neighbours), a fifth of them moved
// to a random place within the grid's span (folds and far throws), weights in [0, 1).
Cells cloth_like(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Cells cells;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      Vec3 corner(i, j, 0.3 * unit(rng));
      if (unit(rng) < 0.2) corner = Vec3(rows * unit(rng), cols * unit(rng), unit(rng));
      Box box;
      box.add(corner);
      box.add(corner + Vec3(1.2, 1.2, 0.2));
      cells.boxes.push_back(box);
      cells.weights.push_back(unit(rng));
    }
  return cells;
}

using PairCount = std::map<std::pair<int, int>, int>;

PairCount tree_pairs(int rows, int cols, const Cells& cells, double window) {
  GridBoxTree tree(rows, cols);
  tree.refit(cells.boxes, cells.weights);
  PairCount found;
  tree.for_each_overlapping_pair([&](double a, double b) { return window <= 0.0 || a + b >= window; },
                                 [&](int a, int b) {
                                   ++found[{a, b}];
                                 });
  return found;
}

PairCount brute_pairs(const Cells& cells, double window) {
  PairCount found;
  const int n = static_cast<int>(cells.boxes.size());
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b)
      if (cells.boxes[a].overlaps(cells.boxes[b]) && (window <= 0.0 || cells.weights[a] + cells.weights[b] >= window))
        ++found[{a, b}];
  return found;
}

TEST(GridBoxTree, FindsEveryOverlappingPairOnceAsBruteForceDoes) {
  std::mt19937 rng(3);
  for (const auto& [rows, cols] : std::vector<std::pair<int, int>>{{1, 1}, {1, 7}, {6, 1}, {5, 8}, {13, 11}}) {
    const Cells cells = cloth_like(rows, cols, rng);
    for (double window : {0.0, 0.9, 1.6}) {
      const PairCount expected = brute_pairs(cells, window), found = tree_pairs(rows, cols, cells, window);
      EXPECT_EQ(found, expected) << rows << " x " << cols << ", window " << window;
      if (rows * cols > 1 && window == 0.0) {
        EXPECT_GT(expected.size(), static_cast<std::size_t>(rows * cols));
      }
    }
  }
}

TEST(GridBoxTree, BoxesThatAllOverlapGiveEveryPair) {
  const int rows = 4, cols = 5, n = rows * cols;
  Cells cells;
  Box box;
  box.add(Vec3::Zero());
  box.add(Vec3::Ones());
  cells.boxes.assign(n, box);
  cells.weights.assign(n, 0.0);
  const PairCount found = tree_pairs(rows, cols, cells, 0.0);
  EXPECT_EQ(found.size(), static_cast<std::size_t>(n * (n + 1) / 2));
  for (const auto& [pair, count] : found) EXPECT_EQ(count, 1) << pair.first << ", " << pair.second;
}

TEST(GridBoxTree, RefusesAnEmptyGrid) {
  EXPECT_TRUE(testing::throws_error([] { GridBoxTree tree(0, 3); }, "grid box tree: "));
}

}  // namespace
}  // namespace fnopt
