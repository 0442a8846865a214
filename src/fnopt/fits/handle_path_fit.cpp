#include <fnopt/fits/handle_path_fit.hpp>

#include <cmath>
#include <limits>

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
  require(std::isfinite(initial_step) && initial_step > 0.0, "initial_step", "must be positive (m)");
  require(std::isfinite(compass_final_step) && compass_final_step > 0.0 && compass_final_step <= initial_step,
          "compass_final_step", "must be positive and at most initial_step (m)");
  record.validate();
}

HandlePathFitResult fit_handle_path(const ResolvedScene& scene, const std::vector<FramePositions>& targets,
                                    HandlePathFitMethod method, const HandlePathFitParams& params,
                                    const std::function<void(const HandlePathFitPoint&)>& on_evaluation) {
  params.validate();
  require(!targets.empty(), "loss", "no target frames");
  const int handles = static_cast<int>(scene.handles.vertices.size());
  require(handles > 0, "handles", "the scene has no handles whose path could be fitted");
  const HandlePath path(params.path, scene.scene.frames - 1, handles);
  const int points = path.control_points();
  const bool with_gradient = method == HandlePathFitMethod::Gradient;

  HandlePathFitResult result;
  double best = std::numeric_limits<double>::infinity();
  VecX best_x;
  // L at x, and with_gradient dL/dx; +inf where the rollout diverges. The history and the best
  // point are kept here, so that both methods are measured alike.
  const auto evaluate = [&](const VecX& x, VecX* gradient) {
    RolloutInputs inputs;
    inputs.handle_targets = path.targets(scene, unflatten(x, handles, points));
    const RecordedRollout rollout = record_rollout(scene, params.record, inputs);
    ++result.passes;
    ++result.evaluations;
    double value = std::numeric_limits<double>::infinity();
    GradientVerdict verdict;
    double radius = 0.0;
    if (rollout.diverged) {
      ++result.diverged_rollouts;
      if (gradient) gradient->setZero(x.size());
    } else {
      const RolloutLoss loss = position_loss(rollout, targets);
      value = loss.value;
      if (gradient) {
        const RolloutGradient adjoint = backpropagate(rollout, loss.gradient);
        ++result.passes;
        result.inexact_gradients += adjoint.status != AdjointStatus::Exact;
        result.ill_conditioned_gradients += adjoint.verdict.conditioning != GradientConditioning::WellConditioned;
        *gradient = flatten(path.control_gradient(adjoint.handle_targets));
        verdict = adjoint.verdict;
        radius = verdict.radius(gradient->norm());
      }
    }
    if (result.evaluations == 1) {
      require(std::isfinite(value), "rollout", "the scene's own motion diverges: " + rollout.divergence);
      result.start_loss = value;
    }
    if (value < best || result.evaluations == 1) {
      best = value;
      best_x = x;
      result.verdict = verdict;
      result.valid_radius = radius;
    }
    result.history.push_back({result.passes, best});
    if (on_evaluation) on_evaluation(result.history.back());
    return value;
  };

  const VecX start = flatten(path.zero_control_points());
  const VecX lower = VecX::Constant(start.size(), -params.bound), upper = VecX::Constant(start.size(), params.bound);
  if (with_gradient) {
    BoundedLbfgsParams lbfgs;
    lbfgs.max_iterations = params.passes;  // the pass budget ends it first
    lbfgs.max_evaluations = params.passes / 2;
    lbfgs.gradient_tolerance = 0.0;
    lbfgs.first_step = params.initial_step;
    const BoundedLbfgsResult fit = minimize_in_box(
        [&](const VecX& x, VecX& gradient) { return evaluate(x, &gradient); }, start, lower, upper, lbfgs);
    result.stop = to_string(fit.status);
  } else {
    const CompassSearchResult fit =
        minimize_by_compass([&](const VecX& x) { return evaluate(x, nullptr); }, start, lower, upper,
                            {params.initial_step, params.compass_final_step, params.passes});
    result.stop = fit.converged ? "converged" : "evaluation-budget";
  }
  result.control = unflatten(best_x, handles, points);
  result.loss = best;
  return result;
}

}  // namespace fnopt
