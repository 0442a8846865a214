#include <fnopt/fits/handle_path_fit.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fnopt/fits/bounded_lbfgs.hpp>
#include <fnopt/fits/compass_search.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// The control points as one vector: handle h's point k, coordinate d at (h K + k) 3 + d.
VecX flatten(const HandleControlPoints& control) {
  const Eigen::Index points = control.empty() ? 0 : static_cast<Eigen::Index>(control[0].size());
  VecX x(3 * points * static_cast<Eigen::Index>(control.size()));
  for (std::size_t h = 0; h < control.size(); ++h)
    for (Eigen::Index k = 0; k < points; ++k) x.segment<3>(3 * (h * points + k)) = control[h][k];
  return x;
}

HandleControlPoints unflatten(const VecX& x, int handles, int points) {
  HandleControlPoints control(handles, std::vector<Vec3>(points));
  for (int h = 0; h < handles; ++h)
    for (int k = 0; k < points; ++k) control[h][k] = x.segment<3>(3 * (h * points + k));
  return control;
}

}  // namespace

const char* to_string(HandlePathFitMethod method) {
  return method == HandlePathFitMethod::Gradient ? "gradient" : "compass";
}

HandlePathFitMethod handle_path_fit_method(const std::string& name) {
  if (name == "gradient") return HandlePathFitMethod::Gradient;
  if (name == "compass") return HandlePathFitMethod::Compass;
  throw Error("method", "expected gradient or compass, got '" + name + "'");
}

void HandlePathFitParams::validate() const {
  path.validate();
  require(std::isfinite(bound) && bound > 0.0, "bound", "must be positive (m)");
  require(passes >= 2, "passes", "must be at least 2 (one forward and one backward pass)");
  smoothing.validate();
  require(std::isfinite(initial_step) && initial_step > 0.0, "initial_step", "must be positive (m)");
  require(std::isfinite(compass_final_step) && compass_final_step > 0.0 && compass_final_step <= initial_step,
          "compass_final_step", "must be positive and at most initial_step (m)");
  record.validate();
}

namespace {

// The loss of the handles' path at control points x, for both methods alike: the passes it takes,
// the history of the best loss, the best point and its gradient's verdict. With smoothing, the
// gradient method's loss and gradient are the smoothed ones (randomized_smoothing.hpp), and the
// history still records the loss at x itself.
class PathLoss {
 public:
  PathLoss(const ResolvedScene& scene, const std::vector<FramePositions>& targets, const HandlePath& path,
           const HandlePathFitParams& params, HandlePathFitResult& result,
           const std::function<void(const HandlePathFitPoint&)>& on_evaluation)
      : scene_(scene), targets_(targets), path_(path), params_(params), result_(result), on_evaluation_(on_evaluation),
        handles_(static_cast<int>(scene.handles.vertices.size())) {
    if (params.smoothing.enabled()) smoothing_.emplace(params.smoothing, handles_ * path.control_points() * 3);
  }

  // L at x (and dL/dx where asked); +inf where the rollout diverges.
  double operator()(const VecX& x, VecX* gradient) {
    ++result_.evaluations;
    double value = 0.0, objective = 0.0;
    GradientVerdict verdict;
    double radius = 0.0;
    if (gradient && smoothing_) {
      value = rollout_loss(x, nullptr, verdict, radius);
      const SmoothedEvaluation smoothed = smoothing_->evaluate(
          [&](const VecX& y, VecX& g) {
            GradientVerdict unused;
            double unused_radius = 0.0;
            return rollout_loss(y, &g, unused, unused_radius);
          },
          x);
      *gradient = smoothed.gradient;
      result_.standard_error = smoothed.standard_error;
      objective = smoothed.value;
    } else {
      value = objective = rollout_loss(x, gradient, verdict, radius);
    }
    if (result_.evaluations == 1) {
      require(std::isfinite(value), "rollout", "the scene's own motion diverges: " + divergence_);
      result_.start_loss = value;
    }
    if (value < best_ || result_.evaluations == 1) {
      best_ = value;
      best_x_ = x;
      result_.verdict = verdict;
      result_.valid_radius = radius;
    }
    result_.history.push_back({result_.passes, best_});
    if (on_evaluation_) on_evaluation_(result_.history.back());
    return objective;
  }
  double best() const { return best_; }
  const VecX& best_x() const { return best_x_; }

 private:
  // One rollout at x, and with `gradient` its backward pass: L(x), +inf where it diverges.
  double rollout_loss(const VecX& x, VecX* gradient, GradientVerdict& verdict, double& radius) {
    RolloutInputs inputs;
    inputs.handle_targets = path_.targets(scene_, unflatten(x, handles_, path_.control_points()));
    const RecordedRollout rollout = record_rollout(scene_, params_.record, inputs);
    ++result_.passes;
    if (rollout.diverged) {
      ++result_.diverged_rollouts;
      divergence_ = rollout.divergence;
      if (gradient) gradient->setZero(x.size());
      return std::numeric_limits<double>::infinity();
    }
    const RolloutLoss loss = position_loss(rollout, targets_);
    if (!gradient) return loss.value;
    const RolloutGradient adjoint = backpropagate(rollout, loss.gradient);
    ++result_.passes;
    result_.inexact_gradients += adjoint.status != AdjointStatus::Exact;
    result_.ill_conditioned_gradients += adjoint.verdict.conditioning != GradientConditioning::WellConditioned;
    *gradient = flatten(path_.control_gradient(adjoint.handle_targets));
    verdict = adjoint.verdict;
    radius = verdict.radius(gradient->norm());
    return loss.value;
  }

  const ResolvedScene& scene_;
  const std::vector<FramePositions>& targets_;
  const HandlePath& path_;
  const HandlePathFitParams& params_;
  HandlePathFitResult& result_;
  const std::function<void(const HandlePathFitPoint&)>& on_evaluation_;
  int handles_;
  std::optional<RandomizedSmoothing> smoothing_;
  std::string divergence_;  // the last diverged rollout's
  double best_ = std::numeric_limits<double>::infinity();
  VecX best_x_;
};

}  // namespace

HandlePathFitResult fit_handle_path(const ResolvedScene& scene, const std::vector<FramePositions>& targets,
                                    HandlePathFitMethod method, const HandlePathFitParams& params,
                                    const std::function<void(const HandlePathFitPoint&)>& on_evaluation) {
  params.validate();
  require(!targets.empty(), "loss", "no target frames");
  const int handles = static_cast<int>(scene.handles.vertices.size());
  require(handles > 0, "handles", "the scene has no handles whose path could be fitted");
  const HandlePath path(params.path, scene.scene.frames - 1, handles);
  HandlePathFitResult result;
  PathLoss loss(scene, targets, path, params, result, on_evaluation);
  // A gradient evaluation takes 2 passes, or 1 + 2 samples with smoothing.
  const int passes_per_gradient = params.smoothing.enabled() ? 1 + 2 * params.smoothing.samples : 2;
  const VecX start = flatten(path.zero_control_points());
  const VecX lower = VecX::Constant(start.size(), -params.bound), upper = VecX::Constant(start.size(), params.bound);
  if (method == HandlePathFitMethod::Gradient) {
    BoundedLbfgsParams lbfgs;
    lbfgs.max_iterations = params.passes;  // the pass budget ends it first
    lbfgs.max_evaluations = std::max(1, params.passes / passes_per_gradient);
    lbfgs.gradient_tolerance = 0.0;
    lbfgs.first_step = params.initial_step;
    const BoundedLbfgsResult fit =
        minimize_in_box([&](const VecX& x, VecX& gradient) { return loss(x, &gradient); }, start, lower, upper, lbfgs);
    result.stop = to_string(fit.status);
  } else {
    const CompassSearchResult fit =
        minimize_by_compass([&](const VecX& x) { return loss(x, nullptr); }, start, lower, upper,
                            {params.initial_step, params.compass_final_step, params.passes});
    result.stop = fit.converged ? "converged" : "evaluation-budget";
  }
  result.control = unflatten(loss.best_x(), handles, path.control_points());
  result.loss = loss.best();
  return result;
}

}  // namespace fnopt
