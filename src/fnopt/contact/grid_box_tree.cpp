#include <fnopt/contact/grid_box_tree.hpp>

#include <fnopt/util/error.hpp>

namespace fnopt {

GridBoxTree::GridBoxTree(int rows, int cols) {
  require(rows >= 1 && cols >= 1, "grid box tree", "needs at least one cell");
  nodes_.reserve(2 * static_cast<std::size_t>(rows) * cols);
  build(0, rows, 0, cols, cols);
}

int GridBoxTree::build(int i0, int i1, int j0, int j1, int cols) {
  const int n = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (i1 - i0 == 1 && j1 - j0 == 1) {
    nodes_[n].cell = i0 * cols + j0;
    return n;
  }
  int first, second;
  if (i1 - i0 >= j1 - j0) {
    const int mid = (i0 + i1) / 2;
    first = build(i0, mid, j0, j1, cols);
    second = build(mid, i1, j0, j1, cols);
  } else {
    const int mid = (j0 + j1) / 2;
    first = build(i0, i1, j0, mid, cols);
    second = build(i0, i1, mid, j1, cols);
  }
  nodes_[n].first = first;
  nodes_[n].second = second;
  return n;
}

void GridBoxTree::refit(const std::vector<Box>& cell_boxes, const std::vector<double>& cell_weights) {
  for (auto n = static_cast<int>(nodes_.size()) - 1; n >= 0; --n) {
    Node& node = nodes_[n];
    if (node.cell >= 0) {
      node.box = cell_boxes[node.cell];
      node.weight = cell_weights[node.cell];
    } else {
      node.box = nodes_[node.first].box;
      node.box.add(nodes_[node.second].box);
      node.weight = std::max(nodes_[node.first].weight, nodes_[node.second].weight);
    }
  }
}

}  // namespace fnopt
