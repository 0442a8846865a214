#pragma once
// How far an exact rollout gradient is a guide (docs/design.md §15). Along a perturbation e d of
// the start positions, d = g / |g| the direction of their gradient g, the rollout's states are
// x_f(e) = x_f + e dx_f + e^2/2 ddx_f + ...; the first- and second-order tangents dx, ddx take one
// more linearised pass, forward (gradient_verdict.cpp). The gradient is a guide while every frame's
// second-order term stays below a tenth of its first-order one:
//   R_0 = min_f 0.2 |dx_f| / |ddx_f|   (over the frames up to the loss's last),
// the loss then changes by rho = R_0 |g|, and a gradient g' of any other parameter kind is taken to
// hold for perturbations along it below rho / |g'| (radius()): the same steps, reached through the
// same modes. The tangents leave out the lagged friction's dependence on the start of the step.
// The record's own states are off by its solves' residuals: step s's, r_s [m/s^2], moves its result
// by about dt^2 r_s sqrt(3n) (the inertia's response), a start perturbation of that over |dx_{s+1}|;
// summed over the steps it is forward_error, and where it reaches R_0 the gradient is no more exact
// than the states it linearises (precision, the derivative's relative change 0.2 forward_error / R_0).
#include <fnopt/adjoint/recorded_rollout.hpp>

namespace fnopt {

enum class GradientConditioning {
  NotMeasured,      // AdjointParams::verdict off, or the backward pass did not complete
  WellConditioned,  // the start positions' R_0 is at least well_conditioned_fraction of an edge
  IllConditioned,   // exact, but valid only for perturbations below R
  BelowPrecision,   // the forward solves' own error is beyond R_0: the gradient is not a derivative
};
const char* to_string(GradientConditioning conditioning);

struct GradientVerdict {
  // The start positions' R_0, as a fraction of the grid's edge, from which a gradient is well conditioned.
  static constexpr double well_conditioned_fraction = 1e-3;

  GradientConditioning conditioning = GradientConditioning::NotMeasured;
  double start_radius = 0.0;  // R_0 [m]
  double loss_radius = 0.0;   // rho [the loss's unit]
  int binding_frame = -1;     // the frame whose ratio is R_0
  double log_growth = 0.0;    // ln max_f |dx_f|: how much the rollout amplifies a start perturbation
  double forward_error = 0.0; // the solves' residuals as a start perturbation [m]
  double precision = 0.0;     // 0.2 forward_error / R_0: the gradient's relative error from them
  double measure_ms = 0.0;    // the verdict's own cost

  // R [the parameter's unit] along a gradient of norm `gradient_norm` (infinite for a zero one).
  double radius(double gradient_norm) const;
};

// The verdict of a rollout's gradient whose start positions' part is `start_gradient`, for a loss
// on frames up to `last_loss_frame`. Throws what StepStates::load throws for a checkpointed record.
GradientVerdict gradient_verdict(const RecordedRollout& rollout, const VecX& start_gradient, int last_loss_frame);

}  // namespace fnopt
