// The bounding-volume hierarchy: every query reports exactly the boxes that overlap it, each once,
// after a build and after a refit that moves every box, on boxes of widely varying sizes; the
// branch-and-bound nearest search finds the smallest value of every box tried; Box::squared_distance
// is the distance of the boxes' closest points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
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

// n random boxes of sizes up to `size` in [-1, 1]^3.
std::vector<Box> boxes_of_size(int n, double size, std::mt19937& rng) {
  std::uniform_real_distribution<double> at(-1.0, 1.0), extent(0.0, size);
  std::vector<Box> boxes(n);
  for (Box& b : boxes) {
    const Vec3 corner(at(rng), at(rng), at(rng));
    b.add(corner);
    b.add(corner + Vec3(extent(rng), extent(rng), extent(rng)));
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
    if (count > 0) {
      EXPECT_TRUE(tree.bounds().lower == all.lower && tree.bounds().upper == all.upper);
    }
  }
}

TEST(Box, SquaredDistanceIsThatOfTheClosestPointsAndZeroWhereBoxesOverlap) {
  Box a, b;
  a.add(Vec3(0, 0, 0));
  a.add(Vec3(1, 1, 1));
  b.add(Vec3(2, 1.5, 0.5));
  b.add(Vec3(3, 4, 0.75));
  EXPECT_DOUBLE_EQ(a.squared_distance(b), 1.0 + 0.25);  // x gap 1, y gap 0.5, z overlaps
  EXPECT_DOUBLE_EQ(b.squared_distance(a), a.squared_distance(b));
  Box point;
  point.add(Vec3(0.5, 0.5, -2));
  EXPECT_DOUBLE_EQ(a.squared_distance(point), 4.0);
  b.add(Vec3(1, 1, 1));  // now touching a's corner
  EXPECT_EQ(a.squared_distance(b), 0.0);
}

// The primitives are the boxes' centres; the search's value is the squared distance from a query
// point to the nearest centre, found with the boxes as bounds.
TEST(BoxTree, NearestFindsTheSmallestValueOfEveryBoxTried) {
  std::mt19937 rng(5);
  for (const int n : {1, 3, 4, 5, 17, 400}) {
    const std::vector<Box> boxes = boxes_of_size(n, 0.3, rng);
    BoxTree tree;
    tree.build(boxes);
    for (const Box& query : boxes_of_size(30, 0.0, rng)) {
      const Vec3 p = query.lower;
      auto centre_distance = [&](int k) { return (p - 0.5 * (boxes[k].lower + boxes[k].upper)).squaredNorm(); };
      int calls = 0;
      const double found = tree.nearest([&](const Box& box) { return box.squared_distance(query); },
                                        [&](int k) { return ++calls, centre_distance(k); });
      double expected = std::numeric_limits<double>::infinity();
      for (int k = 0; k < n; ++k) expected = std::min(expected, centre_distance(k));
      EXPECT_EQ(found, expected) << n << " boxes";
      EXPECT_LE(calls, n);
      // A smaller value known already is returned as it is; a larger one does not hide the nearest.
      EXPECT_EQ(
          tree.nearest([&](const Box& box) { return box.squared_distance(query); }, centre_distance, 0.5 * expected),
          0.5 * expected);
      EXPECT_EQ(tree.nearest([&](const Box& box) { return box.squared_distance(query); }, centre_distance,
                             2.0 * expected + 1e-9),
                expected);
    }
  }
}

TEST(BoxTree, NearestOfAnEmptyTreeIsTheValueGiven) {
  BoxTree tree;
  tree.build({});
  auto bound = [](const Box&) { return 0.0; };
  auto value = [](int) { return 0.0; };
  EXPECT_EQ(tree.nearest(bound, value), std::numeric_limits<double>::infinity());
  EXPECT_EQ(tree.nearest(bound, value, 2.0), 2.0);
}

// A search far from most boxes evaluates few of them.
TEST(BoxTree, NearestSkipsTheFarBoxes) {
  std::mt19937 rng(8);
  const std::vector<Box> boxes = boxes_of_size(4000, 0.01, rng);
  BoxTree tree;
  tree.build(boxes);
  Box query;
  query.add(boxes[17].lower);
  int calls = 0;
  const double found = tree.nearest([&](const Box& box) { return box.squared_distance(query); },
                                    [&](int k) { return ++calls, boxes[k].squared_distance(query); });
  EXPECT_EQ(found, 0.0);
  EXPECT_LT(calls, 100);
}

}  // namespace
}  // namespace fnopt
