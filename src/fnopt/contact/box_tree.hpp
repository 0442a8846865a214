#pragma once
// A bounding-volume hierarchy of axis-aligned boxes: the broad phase of mesh obstacles
// (docs/design.md §14), whose triangles, unlike a grid's cells (grid_box_tree.hpp), come in any
// size and order. Built once over a mesh's primitives (top-down, each node split at the median of
// its boxes' centres along the longest axis of their centres' box, leaves of up to kLeafSize), and
// refitted (the boxes move, the tree keeps its shape) when an animated mesh moves: a refit keeps
// every query exact, only less tight if the motion is large.
//
// Besides the overlap query, a branch-and-bound search for the smallest value of a distance over
// the primitives (nearest()): the closest-approach metrics (metrics/obstacle_distance.hpp).
#include <algorithm>
#include <limits>
#include <vector>

#include <fnopt/contact/box.hpp>

namespace fnopt {

class BoxTree {
 public:
  static constexpr int kLeafSize = 4;

  // Builds the tree over `boxes` (copied; none is required).
  void build(const std::vector<Box>& boxes);
  // New boxes for the same primitives (as many as at build()): each node's box is recomputed.
  void refit(const std::vector<Box>& boxes);

  int size() const { return static_cast<int>(boxes_.size()); }
  const Box& box(int k) const { return boxes_[k]; }
  // The box around all (empty: lower > upper when there is none).
  Box bounds() const { return nodes_.empty() ? Box{} : nodes_.front().box; }

  // Calls visit(k) once for every primitive k whose box overlaps `query` (closed boxes).
  template <class Visit>
  void for_each_overlap(const Box& query, Visit&& visit) const {
    if (nodes_.empty()) return;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!node.box.overlaps(query)) continue;
      if (node.count > 0) {
        for (int e = node.first; e < node.first + node.count; ++e)
          if (boxes_[order_[e]].overlaps(query)) visit(order_[e]);
        continue;
      }
      stack[top++] = node.first;  // the left child; the right one follows it
      stack[top++] = node.first + 1;
    }
  }

  // The smallest distance(k) over the primitives k, or `best` where that is smaller (+inf: none
  // known). bound(box) must be a lower bound on distance(k) for every primitive whose box lies
  // inside `box` (Box::squared_distance to a query's box, for a squared distance). Visits the
  // nearer child first and skips every node and primitive whose bound is not below the smallest
  // value found so far, so a small `best` (a value known from earlier queries) skips most of the
  // tree: only values below it are looked for.
  template <class Bound, class Distance>
  double nearest(Bound&& bound, Distance&& distance, double best = std::numeric_limits<double>::infinity()) const {
    if (nodes_.empty()) return best;
    struct Entry {
      int node;
      double bound;
    };
    Entry stack[64];  // a depth-first search holds at most one sibling per level
    int top = 0;
    stack[top++] = {0, bound(nodes_.front().box)};
    while (top > 0) {
      const Entry entry = stack[--top];
      if (!(entry.bound < best)) continue;
      const Node& node = nodes_[entry.node];
      if (node.count > 0) {
        for (int e = node.first; e < node.first + node.count; ++e)
          if (bound(boxes_[order_[e]]) < best) best = std::min(best, static_cast<double>(distance(order_[e])));
        continue;
      }
      const Entry left{node.first, bound(nodes_[node.first].box)};
      const Entry right{node.first + 1, bound(nodes_[node.first + 1].box)};
      stack[top++] = left.bound < right.bound ? right : left;  // the farther one waits
      stack[top++] = left.bound < right.bound ? left : right;
    }
    return best;
  }

 private:
  struct Node {
    Box box;
    int first = 0;  // a leaf: its first entry of order_; an inner node: its left child
    int count = 0;  // a leaf: its entries; 0 for an inner node
  };
  // Splits the entries [begin, end) under node `index`.
  void split(int index, int begin, int end);
  // Recomputes node `index`'s box from its children or entries.
  void refit_node(int index);

  std::vector<Box> boxes_;
  std::vector<int> order_;  // primitive indices, each leaf's a contiguous range
  std::vector<Node> nodes_;  // nodes_[0] the root; an inner node's children are adjacent
};

}  // namespace fnopt
