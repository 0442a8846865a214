#include <fnopt/metrics/kd_tree.hpp>

#include <algorithm>
#include <limits>
#include <numeric>

namespace fnopt {
namespace {
constexpr int kLeafSize = 8;
}

KdTree3::KdTree3(std::vector<Vec3> points) : points_(std::move(points)), order_(points_.size()) {
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(4 * points_.size() / kLeafSize + 2);
  if (!points_.empty()) root_ = build(0, static_cast<int>(points_.size()));
  sorted_.reserve(points_.size());
  for (int index : order_) sorted_.push_back(points_[index]);
}

int KdTree3::build(int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int k = begin; k < end; ++k) {
    lo = lo.cwiseMin(points_[order_[k]]);
    hi = hi.cwiseMax(points_[order_[k]]);
  }
  nodes_.push_back(Node{begin, end, -1, -1, lo, hi});
  if (end - begin <= kLeafSize) return id;
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                   [&](int a, int b) { return points_[a][axis] < points_[b][axis]; });
  const int left = build(begin, middle);
  const int right = build(middle, end);
  nodes_[id].left = left;
  nodes_[id].right = right;
  return id;
}

void KdTree3::search(int id, const Vec3& query, Neighbour& best) const {
  const Node& node = nodes_[id];
  if (node.left < 0) {
    for (int k = node.begin; k < node.end; ++k) {
      const double d2 = (sorted_[k] - query).squaredNorm();
      if (d2 < best.squared_distance) best = {order_[k], d2};
    }
    return;
  }
  const double d_left = box_distance2(nodes_[node.left], query);
  const double d_right = box_distance2(nodes_[node.right], query);
  const bool left_first = d_left <= d_right;
  const int first = left_first ? node.left : node.right, second = left_first ? node.right : node.left;
  const double d_first = left_first ? d_left : d_right, d_second = left_first ? d_right : d_left;
  if (d_first < best.squared_distance) search(first, query, best);
  if (d_second < best.squared_distance) search(second, query, best);
}

KdTree3::Neighbour KdTree3::nearest(const Vec3& query) const {
  Neighbour best{-1, std::numeric_limits<double>::infinity()};
  if (root_ >= 0) search(root_, query, best);
  return best;
}

}  // namespace fnopt
