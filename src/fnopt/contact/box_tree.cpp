#include <fnopt/contact/box_tree.hpp>

#include <algorithm>

#include <fnopt/util/error.hpp>

namespace fnopt {

void BoxTree::build(const std::vector<Box>& boxes) {
  boxes_ = boxes;
  order_.resize(boxes_.size());
  for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<int>(k);
  nodes_.clear();
  if (boxes_.empty()) return;
  nodes_.reserve(2 * boxes_.size() / kLeafSize + 2);
  nodes_.emplace_back();
  split(0, 0, static_cast<int>(order_.size()));
}

void BoxTree::split(int index, int begin, int end) {
  Box centres;
  Box all;
  for (int e = begin; e < end; ++e) {
    const Box& b = boxes_[order_[e]];
    all.add(b);
    centres.add(0.5 * (b.lower + b.upper));
  }
  nodes_[index].box = all;
  // Depth is at most log2(n / kLeafSize) + 1 with median splits: well inside the query's stack.
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return;
  }
  Eigen::Index axis = 0;
  (centres.upper - centres.lower).maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end, [&](int a, int b) {
    return boxes_[a].lower[axis] + boxes_[a].upper[axis] < boxes_[b].lower[axis] + boxes_[b].upper[axis];
  });
  const int left = static_cast<int>(nodes_.size());
  nodes_[index].first = left;
  nodes_[index].count = 0;
  nodes_.emplace_back();
  nodes_.emplace_back();
  split(left, begin, middle);
  split(left + 1, middle, end);
}

void BoxTree::refit(const std::vector<Box>& boxes) {
  require(boxes.size() == boxes_.size(), "box tree", "refit with a different number of boxes");
  boxes_ = boxes;
  if (!nodes_.empty()) refit_node(0);
}

void BoxTree::refit_node(int index) {
  Node& node = nodes_[index];
  Box box;
  if (node.count > 0) {
    for (int e = node.first; e < node.first + node.count; ++e) box.add(boxes_[order_[e]]);
  } else {
    refit_node(node.first);
    refit_node(node.first + 1);
    box.add(nodes_[node.first].box);
    box.add(nodes_[node.first + 1].box);
  }
  nodes_[index].box = box;
}

}  // namespace fnopt
