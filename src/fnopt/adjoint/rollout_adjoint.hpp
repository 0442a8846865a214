#pragma once
// The backward pass of a recorded rollout (docs/design.md §15): the gradient of a loss on the
// rollout's positions with respect to the material, gravity, the handles' targets at every step
// and the initial state, by the adjoint of the exact steps.
//
// Step s from (x_s, v_s) to (x_{s+1}, v_{s+1}): the handles' accelerations are prescribed,
// a_H = (y_s - x_s - dt v_s)/dt^2 (y_s their targets), the free ones solve g_F = 0
// (step_linearization.hpp), and x_{s+1} = x_s + dt v_s + dt^2 a, v_{s+1} = v_s + dt a. Given the
// adjoints xbar_{s+1}, vbar_{s+1} (the loss's dL/dx at frame s+1 included):
//   abar = dt^2 xbar_{s+1} + dt vbar_{s+1},
//   H_FF lambda = abar_F                         (one solve, the exact Hessian at the result),
//   thetabar -= lambda^T dg_F/dtheta,
//   abar_H   -= lambda^T dg_F/da_H = (dt^4 K lambda)_H,
//   ybar_s    = abar_H / dt^2,
//   xbar_s    = xbar_{s+1} - dt^2 K lambda - [abar_H / dt^2 on the handles] + dL/dx_s,
//   vbar_s    = dt xbar_{s+1} + vbar_{s+1} - dt^3 K lambda - dt^2 c M lambda - [abar_H / dt on the handles].
// After step 0, xbar_0 and vbar_0 are the gradient with respect to the initial state. A step after
// the handles are let go (Scene::let_go) has every vertex free: no a_H, and dL/dy_s = 0. A
// checkpointed record's steps are re-simulated segment by segment from its checkpoints, last first.
#include <vector>

#include <fnopt/adjoint/gradient_verdict.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/step_linearization.hpp>

namespace fnopt {

// dL/dx at one frame, every dof (3 per vertex).
struct FrameGradient {
  int frame = 0;
  VecX gradient;
};

struct AdjointParams {
  // Measure how far the linearisation holds (GradientVerdict): per step an inverse iteration and
  // two Hessian assemblies beside the solve.
  bool verdict = true;
  // At a step whose H_FF is indefinite but non-singular (a saddle of the step's energy) the
  // implicit function theorem still holds and the step's branch is differentiable: solve there
  // with the LDL^T factor (the step is listed either way); false stops the backward pass.
  bool solve_at_saddles = true;
};

// Why the gradient is what it is.
enum class AdjointStatus {
  Exact,            // every step at a strict local minimum, every forward solve converged
  ThroughSaddles,   // some steps at saddles (saddle_steps), differentiated on their branch
  Unconverged,      // some forward solves did not converge (unconverged_steps): approximate
  StoppedAtSaddle,  // a saddle with solve_at_saddles off: the gradient is of the steps after it only
  Singular,         // a step's H_FF is singular (singular_step): no gradient through it
};
const char* to_string(AdjointStatus status);
// A complete gradient: Exact, ThroughSaddles or Unconverged.
bool is_complete(AdjointStatus status);

struct RolloutGradient {
  AdjointStatus status = AdjointStatus::Exact;
  MaterialGradient material;      // dL/dk for each coefficient, dL/dgravity
  MaterialGradient log_material;  // k dL/dk = dL/dlog k (gravity: as material.gravity)
  // handle_targets[s][h] = dL/dy_s for handle h's target at frame s + 1.
  std::vector<std::vector<Vec3>> handle_targets;
  VecX initial_positions, initial_velocities;  // dL/dx_0, dL/dv_0
  GradientVerdict verdict;
  std::vector<int> saddle_steps, unconverged_steps;
  int singular_step = -1;  // the step the pass stopped at, -1 if none
  // With checkpoints (RecordOptions::checkpoint_interval): the steps re-simulated, and the largest
  // distance of a re-simulated position from the recorded one [m] (0 where the re-simulation took
  // the recorded path bit for bit).
  int resimulated_steps = 0;
  double resimulation_error = 0.0;
  // The pass's cost: wall time, factorisations (Cholesky, and LDL^T where it fails), solves.
  double backward_ms = 0.0;
  long factorizations = 0;
  long solves = 0;
};

// Throws Error("rollout", ...) for a rollout with no recorded forward pass or one that diverged,
// and Error("loss", ...) for a frame outside the rollout or a gradient of the wrong size.
RolloutGradient backpropagate(const RecordedRollout& rollout, const std::vector<FrameGradient>& loss_gradient,
                              const AdjointParams& params = {});

}  // namespace fnopt
