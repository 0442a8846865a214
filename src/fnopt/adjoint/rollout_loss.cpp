#include <fnopt/adjoint/rollout_loss.hpp>

#include <fnopt/metrics/kd_tree.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

void check_frame(const RecordedRollout& rollout, int frame) {
  require(!rollout.empty(), "rollout", "no recorded forward pass (record_rollout gives one)");
  require(frame >= 0 && frame < rollout.frame_count(), "loss",
          "frame " + std::to_string(frame) + " is outside the rollout's 0.." + std::to_string(rollout.frame_count() - 1));
}

std::vector<Vec3> vertex_points(const VecX& x) {
  std::vector<Vec3> points(x.size() / 3);
  for (std::size_t k = 0; k < points.size(); ++k) points[k] = x.segment<3>(3 * k);
  return points;
}

}  // namespace

RolloutLoss position_loss(const RecordedRollout& rollout, const std::vector<FramePositions>& targets) {
  RolloutLoss loss;
  for (const FramePositions& target : targets) {
    check_frame(rollout, target.frame);
    const VecX& x = rollout.positions[target.frame];
    require(target.positions.size() == x.size(), "loss",
            "frame " + std::to_string(target.frame) + ": expected " + std::to_string(x.size()) +
                " target values (3 per vertex), got " + std::to_string(target.positions.size()));
    const VecX difference = x - target.positions;
    loss.value += difference.squaredNorm();
    loss.gradient.push_back({target.frame, 2.0 * difference});
  }
  return loss;
}

RolloutLoss chamfer_loss(const RecordedRollout& rollout, const std::vector<FramePoints>& observed) {
  RolloutLoss loss;
  for (const FramePoints& frame : observed) {
    check_frame(rollout, frame.frame);
    require(!frame.points.empty(), "loss", "frame " + std::to_string(frame.frame) + ": no observed points");
    const std::vector<Vec3> cloth = vertex_points(rollout.positions[frame.frame]);
    const KdTree3 observed_tree(frame.points);
    const KdTree3 cloth_tree(cloth);
    const double cloth_weight = 1.0 / static_cast<double>(cloth.size());
    const double observed_weight = 1.0 / static_cast<double>(frame.points.size());
    VecX gradient = VecX::Zero(3 * static_cast<Eigen::Index>(cloth.size()));
    for (std::size_t k = 0; k < cloth.size(); ++k) {
      const KdTree3::Neighbour nearest = observed_tree.nearest(cloth[k]);
      loss.value += cloth_weight * nearest.squared_distance;
      gradient.segment<3>(3 * k) += 2.0 * cloth_weight * (cloth[k] - frame.points[nearest.index]);
    }
    for (const Vec3& y : frame.points) {
      const KdTree3::Neighbour nearest = cloth_tree.nearest(y);
      loss.value += observed_weight * nearest.squared_distance;
      gradient.segment<3>(3 * nearest.index) += 2.0 * observed_weight * (cloth[nearest.index] - y);
    }
    loss.gradient.push_back({frame.frame, std::move(gradient)});
  }
  return loss;
}

}  // namespace fnopt
