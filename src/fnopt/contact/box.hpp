#pragma once
// An axis-aligned box: the bounds of the contact broad phases (box_tree.hpp for meshes,
// grid_box_tree.hpp for self-contact; docs/design.md §14).
#include <array>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct Box {
  Vec3 lower = Vec3::Constant(1e300), upper = Vec3::Constant(-1e300);

  void add(const Vec3& p) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  void add(const Box& b) {
    lower = lower.cwiseMin(b.lower);
    upper = upper.cwiseMax(b.upper);
  }
  void grow(double r) {
    lower.array() -= r;
    upper.array() += r;
  }
  bool overlaps(const Box& b) const {
    return (lower.array() <= b.upper.array()).all() && (b.lower.array() <= upper.array()).all();
  }
  bool contains(const Vec3& p) const {
    return (lower.array() <= p.array()).all() && (p.array() <= upper.array()).all();
  }
  // The squared distance between the closed boxes (0 where they overlap): a lower bound on the
  // squared distance between anything inside one and anything inside the other. A point is the
  // box of one point.
  double squared_distance(const Box& b) const {
    return (lower - b.upper).cwiseMax(b.lower - upper).cwiseMax(0.0).squaredNorm();
  }
};

// The squared distance between the boxes of a pair's two primitives, vertices 0 .. split - 1 and
// split .. 3 (a point and a triangle: split 1; two edges: split 2): a lower bound on the squared
// distance of the primitives, which the contact shortcuts test before the exact one.
inline double split_boxes_squared_distance(const std::array<Vec3, 4>& vertices, int split) {
  Box a, b;
  for (int k = 0; k < 4; ++k) (k < split ? a : b).add(vertices[k]);
  return a.squared_distance(b);
}

// A margin [m] far above the rounding of an exact primitive distance and far below any contact
// range: a shortcut on the boxes' distance that keeps this much on the safe side decides as the
// exact test would.
constexpr double kBoxRoundingMargin = 1e-9;

}  // namespace fnopt
