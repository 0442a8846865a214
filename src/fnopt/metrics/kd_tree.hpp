#pragma once
// A small static k-d tree over 3-D points for exact nearest-neighbour queries (the Chamfer
// distance's inner loop). Built once by median splits along the axis of largest extent,
// leaves of at most 8 points stored contiguously; every node keeps the bounding box of its
// points, and a query visits the nearer child box first and skips any box farther than the
// best distance found. Box (not split-plane) pruning keeps queries fast when they lie far from
// the points, as they do for a rollout far from its reference.
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class KdTree3 {
 public:
  explicit KdTree3(std::vector<Vec3> points);

  struct Neighbour {
    int index = -1;  // into the points given to the constructor, -1 if there are none
    double squared_distance = 0.0;
  };
  Neighbour nearest(const Vec3& query) const;

  int size() const { return static_cast<int>(points_.size()); }
  const Vec3& point(int index) const { return points_[index]; }

 private:
  struct Node {
    int begin = 0, end = 0;     // range of sorted_ (leaves)
    int left = -1, right = -1;  // -1: leaf
    Vec3 lo, hi;                // bounding box of the node's points
  };
  int build(int begin, int end);
  void search(int node, const Vec3& query, Neighbour& best) const;
  double box_distance2(const Node& node, const Vec3& query) const {
    return (node.lo - query).cwiseMax(query - node.hi).cwiseMax(0.0).squaredNorm();
  }

  std::vector<Vec3> points_;
  std::vector<int> order_;  // sorted_[k] = points_[order_[k]]
  std::vector<Vec3> sorted_;
  std::vector<Node> nodes_;
  int root_ = -1;
};

}  // namespace fnopt
