#pragma once
// A bounding-box hierarchy over the cells of a rows x cols grid, by (i, j) blocks: the broad phase
// of self-contact's far pairs (docs/design.md §14). Its shape is the grid's, fixed at construction:
// each node holds a block of cells, split across its longer side into halves, down to single cells.
// Each search refits it bottom-up from the cells' boxes (one pass, no sorting), then walks it against
// itself: two nodes whose boxes do not overlap hold no pair, and a cloth's blocks overlap mostly
// their neighbours in (i, j), so a search visits about as many node pairs as there are overlapping
// cell pairs. A hash of the cells' boxes found the same pairs by scanning about a hundred binned
// boxes a query.
#include <algorithm>
#include <vector>

#include <fnopt/contact/box.hpp>

namespace fnopt {

class GridBoxTree {
 public:
  GridBoxTree() = default;  // no cells
  // Cells in row-major order, rows x cols (both >= 1).
  GridBoxTree(int rows, int cols);

  // Refits every node to `cell_boxes` (rows x cols of them) and `cell_weights` (a number per cell;
  // each node keeps its cells' largest).
  void refit(const std::vector<Box>& cell_boxes, const std::vector<double>& cell_weights);

  // Calls visit(a, b) once for every unordered pair of cells a <= b (a cell with itself too) whose
  // boxes overlap (closed boxes), unless keep(wa, wb) is false for the nodes' largest weights wa, wb
  // that hold them: keep must be monotone (false for weights stays false for smaller ones), so that
  // a pair of nodes it refuses holds no pair it would keep.
  template <class Keep, class Visit>
  void for_each_overlapping_pair(Keep&& keep, Visit&& visit) const {
    if (!nodes_.empty()) self(0, keep, visit);
  }

 private:
  struct Node {
    Box box;
    double weight = 0.0;
    int cell = -1;                // a leaf's cell, -1 for an inner node
    int first = -1, second = -1;  // an inner node's children
  };

  // Appends the node of cells [i0, i1) x [j0, j1) and its subtree (children after their parent).
  int build(int i0, int i1, int j0, int j1, int cols);
  static double extent(const Box& box) { return (box.upper - box.lower).squaredNorm(); }

  template <class Keep, class Visit>
  void self(int n, Keep& keep, Visit& visit) const {
    const Node& node = nodes_[n];
    if (node.cell >= 0) {
      if (keep(node.weight, node.weight)) visit(node.cell, node.cell);
      return;
    }
    self(node.first, keep, visit);
    self(node.second, keep, visit);
    pair(node.first, node.second, keep, visit);
  }

  template <class Keep, class Visit>
  void pair(int a, int b, Keep& keep, Visit& visit) const {
    const Node &na = nodes_[a], &nb = nodes_[b];
    if (!keep(na.weight, nb.weight) || !na.box.overlaps(nb.box)) return;
    if (na.cell >= 0 && nb.cell >= 0) {
      visit(std::min(na.cell, nb.cell), std::max(na.cell, nb.cell));
    } else if (nb.cell >= 0 || (na.cell < 0 && extent(na.box) >= extent(nb.box))) {
      pair(na.first, b, keep, visit);
      pair(na.second, b, keep, visit);
    } else {
      pair(a, nb.first, keep, visit);
      pair(a, nb.second, keep, visit);
    }
  }

  std::vector<Node> nodes_;  // nodes_[0] the root; every node before its children
};

}  // namespace fnopt
