#include <fnopt/adjoint/rollout_loss.hpp>

#include <algorithm>

#include <fnopt/metrics/kd_tree.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

void check_frame(const RecordedRollout& rollout, int frame) {
  require(!rollout.empty(), "rollout", "no recorded forward pass (record_rollout gives one)");
  require(
      frame >= 0 && frame < rollout.frame_count(), "loss",
      "frame " + std::to_string(frame) + " is outside the rollout's 0.." + std::to_string(rollout.frame_count() - 1));
}

std::vector<Vec3> vertex_points(const VecX& x) {
  std::vector<Vec3> points(x.size() / 3);
  for (std::size_t k = 0; k < points.size(); ++k) points[k] = x.segment<3>(3 * k);
  return points;
}

// CD(P, Y) = mean_{p in P} min_y |p - y|^2 + mean_{y in Y} min_p |p - y|^2 and its gradient with
// respect to each p (3 per point), nearest neighbours held fixed:
//   dCD/dp = (2/|P|)(p - nn_Y(p)) + (2/|Y|) sum_{y : nn_P(y) = p} (p - y),
// and its Hessian's diagonal there, per point: 2/|P| + (2/|Y|) |{y : nn_P(y) = p}|.
double point_chamfer(const std::vector<Vec3>& points, const std::vector<Vec3>& observed, VecX& gradient,
                     VecX& curvature) {
  const KdTree3 observed_tree(observed);
  const KdTree3 points_tree(points);
  const double point_weight = 1.0 / static_cast<double>(points.size());
  const double observed_weight = 1.0 / static_cast<double>(observed.size());
  double value = 0.0;
  gradient = VecX::Zero(3 * static_cast<Eigen::Index>(points.size()));
  curvature = VecX::Constant(static_cast<Eigen::Index>(points.size()), 2.0 * point_weight);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const KdTree3::Neighbour nearest = observed_tree.nearest(points[k]);
    value += point_weight * nearest.squared_distance;
    gradient.segment<3>(3 * k) += 2.0 * point_weight * (points[k] - observed[nearest.index]);
  }
  for (const Vec3& y : observed) {
    const KdTree3::Neighbour nearest = points_tree.nearest(y);
    value += observed_weight * nearest.squared_distance;
    gradient.segment<3>(3 * nearest.index) += 2.0 * observed_weight * (points[nearest.index] - y);
    curvature[static_cast<Eigen::Index>(nearest.index)] += 2.0 * observed_weight;
  }
  return value;
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
    loss.gauss_newton_weights.push_back(VecX::Constant(x.size(), 2.0));
  }
  return loss;
}

RolloutLoss chamfer_loss(const RecordedRollout& rollout, const std::vector<FramePoints>& observed) {
  RolloutLoss loss;
  for (const FramePoints& frame : observed) {
    check_frame(rollout, frame.frame);
    require(!frame.points.empty(), "loss", "frame " + std::to_string(frame.frame) + ": no observed points");
    const std::vector<Vec3> cloth = vertex_points(rollout.positions[frame.frame]);
    VecX gradient, curvature;
    loss.value += point_chamfer(cloth, frame.points, gradient, curvature);
    loss.gradient.push_back({frame.frame, std::move(gradient)});
    loss.gauss_newton_weights.push_back(curvature.replicate(1, 3).transpose().reshaped());
  }
  return loss;
}

RolloutLoss surface_chamfer_loss(const RecordedRollout& rollout, const std::vector<FramePoints>& observed,
                                 const ChamferOptions& options) {
  options.validate();
  RolloutLoss loss;
  const double frame_weight = 1.0 / static_cast<double>(std::max<std::size_t>(1, observed.size()));
  const Triangles triangles = rollout.scene.grid.triangles();
  for (const FramePoints& frame : observed) {
    check_frame(rollout, frame.frame);
    require(!frame.points.empty(), "loss", "frame " + std::to_string(frame.frame) + ": no observed points");
    const VecX& x = rollout.positions[frame.frame];
    const std::vector<SurfacePoint> samples = sample_surface_points(x, triangles, options.samples, options.seed);
    VecX point_gradient, point_curvature;
    loss.value += frame_weight * point_chamfer(surface_point_positions(x, triangles, samples), frame.points,
                                               point_gradient, point_curvature);
    // A sample's curvature c spreads over its triangle's corners as c w w^T; lumped, corner i gets c w_i.
    VecX gradient = VecX::Zero(x.size()), weights = VecX::Zero(x.size());
    for (std::size_t k = 0; k < samples.size(); ++k)
      for (int i = 0; i < 3; ++i) {
        const Eigen::Index corner = 3 * static_cast<Eigen::Index>(triangles(samples[k].face, i));
        const double w = frame_weight * samples[k].weights[i];
        gradient.segment<3>(corner) += w * point_gradient.segment<3>(3 * static_cast<Eigen::Index>(k));
        weights.segment<3>(corner).array() += w * point_curvature[static_cast<Eigen::Index>(k)];
      }
    loss.gradient.push_back({frame.frame, std::move(gradient)});
    loss.gauss_newton_weights.push_back(std::move(weights));
  }
  return loss;
}

}  // namespace fnopt
