#pragma once
// Handle paths fitted to a target shape (docs/design.md §15): the control points c of the
// handles' path offsets (handle_path.hpp) whose rollout of exact steps brings the cloth to target
// positions at chosen frames,
//   L(c) = sum over the target frames f of sum_i |x_f,i(c) - target_f,i|^2   [m^2],
// every coordinate of every control point within [-bound, bound]. Two methods on the same L:
//  * Gradient: projected L-BFGS (bounded_lbfgs.hpp) on the adjoint gradient dL/dc
//    (rollout_adjoint.hpp, then HandlePath::control_gradient), one forward and one backward pass
//    per evaluation;
//  * Compass: the compass search (compass_search.hpp) on L alone, one forward pass per evaluation,
//    the gradient-free baseline.
// Both get the same budget of passes, a backward pass counted as one, and return the best point
// they evaluated.
#include <functional>
#include <string>
#include <vector>

#include <fnopt/adjoint/gradient_verdict.hpp>
#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/fits/randomized_smoothing.hpp>

namespace fnopt {

enum class HandlePathFitMethod { Gradient, Compass };
const char* to_string(HandlePathFitMethod method);
// "gradient" or "compass"; throws Error("method", ...) for another name.
HandlePathFitMethod handle_path_fit_method(const std::string& name);

struct HandlePathFitParams {
  HandlePathParams path{HandlePathBasis::CubicBSpline, 4};
  double bound = 0.5;  // |c| per coordinate [m]
  int passes = 60;     // forward and backward passes at most
  // The first move [m]: the compass's first poll step, and the largest coordinate of L-BFGS's first
  // step (BoundedLbfgsParams::first_step); the compass stops below its final step.
  double initial_step = 0.1;
  double compass_final_step = 1e-4;
  // The gradient method on the loss smoothed over perturbations of the control points [m]
  // (randomized_smoothing.hpp): a gradient evaluation then takes one forward pass at the point and a
  // forward and a backward pass per sample. Off by default (sigma 0).
  SmoothingParams smoothing;
  // The forward passes' exact steps; the Hessians are classified by the backward pass alone.
  RecordOptions record = [] {
    RecordOptions options;
    options.classify_steps = false;
    return options;
  }();

  void validate() const;  // throws Error naming the field
};

// The best loss found after a number of passes.
struct HandlePathFitPoint {
  int passes = 0;
  double loss = 0.0;
};

struct HandlePathFitResult {
  HandleControlPoints control;              // the best evaluated
  double start_loss = 0.0;                  // at zero offsets: the scene's own motion
  double loss = 0.0;                        // at `control`
  int passes = 0;                           // forward and backward passes used
  int evaluations = 0;                      // of L
  std::string stop;                         // why the method stopped
  std::vector<HandlePathFitPoint> history;  // after every evaluation
  int diverged_rollouts = 0;                // trial paths whose rollout diverged (L = +inf there)
  int inexact_gradients = 0;                // gradient evaluations whose backward pass was not Exact
  // Gradient evaluations whose verdict was not well-conditioned; the verdict of the gradient at the
  // best point evaluated (NotMeasured for the compass), and its radius along dL/dc there [m].
  int ill_conditioned_gradients = 0;
  GradientVerdict verdict;
  double valid_radius = 0.0;
  double standard_error = 0.0;  // with smoothing: the last smoothed gradient's (randomized_smoothing.hpp)
};

// Fits the handles' path of `scene` (its motion plus the offsets) to `targets` from zero
// offsets; `on_evaluation` sees the history's every new point. Throws Error("loss", ...) for
// targets that do not fit the scene, what record_rollout throws (a scene with obstacles), and
// Error("rollout", ...) if the scene's own motion diverges.
HandlePathFitResult fit_handle_path(const ResolvedScene& scene, const std::vector<FramePositions>& targets,
                                    HandlePathFitMethod method, const HandlePathFitParams& params = {},
                                    const std::function<void(const HandlePathFitPoint&)>& on_evaluation = {});

}  // namespace fnopt
