// The bounding-volume hierarchy: every query reports exactly the boxes that overlap it, each once,
// after a build and after a refit that moves every box, on boxes of widely varying sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include <fnopt/contact/box_tree.hpp>

namespace fnopt {
namespace {

std::vector<Box> random_boxes(std::mt19937& random, int count) {
  std::uniform_real_distribution<double> position(-1.0, 1.0), size(0.0, 1.0);
  std::vector<Box> boxes(count);
  for (Box& box : boxes) {
    const Vec3 corner(position(random), position(random), position(random));
    const double scale = std::pow(10.0, -3.0 * size(random));  // from 1 mm to 1 m
    box.add(corner);
    box.add(corner + scale * Vec3(size(random), size(random), size(random)));
  }
  return boxes;
}

void expect_queries_match_brute_force(const BoxTree& tree, const std::vector<Box>& boxes, std::mt19937& random) {
  for (const Box& query : random_boxes(random, 200)) {
    std::vector<int> found, expected;
    tree.for_each_overlap(query, [&](int k) { found.push_back(k); });
    for (int k = 0; k < static_cast<int>(boxes.size()); ++k)
      if (boxes[k].overlaps(query)) expected.push_back(k);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected);
  }
}

TEST(BoxTree, QueriesFindExactlyTheOverlappingBoxesAfterBuildAndRefit) {
  std::mt19937 random(7);
  for (int count : {0, 1, 3, 4, 5, 100, 1000}) {
    std::vector<Box> boxes = random_boxes(random, count);
    BoxTree tree;
    tree.build(boxes);
    EXPECT_EQ(tree.size(), count);
    expect_queries_match_brute_force(tree, boxes, random);
    for (Box& box : boxes) {  // every box moves, the tree keeps its shape
      const Vec3 shift = Vec3::Random();
      box.lower += shift;
      box.upper += shift;
    }
    tree.refit(boxes);
    expect_queries_match_brute_force(tree, boxes, random);
    Box all;
    for (const Box& box : boxes) all.add(box);
    if (count > 0) EXPECT_TRUE(tree.bounds().lower == all.lower && tree.bounds().upper == all.upper);
  }
}

}  // namespace
}  // namespace fnopt
