#pragma once
// The recorded forward pass of a rollout's adjoint (docs/design.md §15): a rollout of exact
// backward-Euler steps, every step's state, acceleration and handle targets kept in memory.
//
// An adjoint needs each step at a stationary point of its energy (the implicit function theorem
// differentiates g_F = 0), so every step ends with the Newton reference (baselines/newton.hpp)
// run to a tight residual acceleration: either Newton solves the step alone, or any inner
// optimizer solves it and Newton polishes its result (polished steps are counted); then exact
// Newton steps with a direct solve take the result to the objective's precision. Each step's
// exact Hessian on its free dofs is classified at the result (adjoint/step_linearization.hpp): a
// saddle or a singular point is reported here and again by the backward pass, never passed over.
#include <optional>
#include <string>
#include <vector>

#include <fnopt/adjoint/step_linearization.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

struct RecordOptions {
  // Newton's stop, residual acceleration in m/s^2 (BackwardEulerObjective::residual_acceleration):
  // nine orders below the reference's 0.1, so that the recorded result is a stationary point to
  // about the precision of the objective; a step that ends at precision-limit first is as close
  // as L resolves (is_converged).
  double acceleration_tolerance = 1e-10;
  int max_newton_iterations = 200;
  // Then at most this many exact Newton steps, a -= H_FF^-1 g_F by a direct solve, each kept only
  // if it lowers the residual: the trust-region iterates solve with CG to a forcing tolerance and
  // stop where L's rounding hides progress, which leaves an error along the softest modes of a
  // nearly singular H_FF (a compressed cloth) far above what the residual suggests.
  int exact_newton_steps = 2;
  // Classify each step's Hessian at its result (one factorisation per step); off: the backward
  // pass alone says it.
  bool classify_steps = true;
  double divergence_strain = 3.0;  // as RolloutOptions: an edge past (1 + this) x rest diverges
  // 0: every frame's velocity and every step's acceleration are kept. K > 0: checkpoints: the
  // velocities only at frames 0, K, 2K, ... and no accelerations (the positions of every frame
  // stay, the losses read them), so the record holds F + F/K vectors of 3n doubles instead of
  // 3F - 1; the backward pass re-simulates each segment of K steps from its checkpoint (one more
  // forward pass in all; K ~ sqrt(F) keeps its buffer of 3K vectors as small as the checkpoints).
  // Newton then refactorises its preconditioner at every step, so that a re-simulated step takes
  // the recorded step's path; Newton alone, without start accelerations.
  int checkpoint_interval = 0;

  void validate() const;  // throws Error naming the field
};

// Where a rollout starts and where its handles go, when not the scene's own.
struct RolloutInputs {
  std::optional<VecX> initial_positions;   // default: the grid's rest positions
  std::optional<VecX> initial_velocities;  // default: zero
  // targets[s][h]: handle h's position at frame s + 1 (one Vec3 per handle vertex, in the order of
  // the scene's handles, one row per step); default: the scene's trajectory at (s + 1) dt.
  std::optional<std::vector<std::vector<Vec3>>> handle_targets;
  // start_accelerations[s]: step s's first iterate on the free dofs (every dof given, the handles'
  // ignored); default: 0, the reference's start. Where a step's energy has several minima (a
  // compressed cloth buckles either way) the solver's path picks one, so a rollout is only
  // piecewise smooth in its inputs; started from a recorded rollout's accelerations, Newton
  // converges to the continuation of each recorded stationary point instead, the branch whose
  // derivative the adjoint gives (gradient_check.hpp's perturbed rollouts).
  std::optional<std::vector<VecX>> start_accelerations;
};

struct RecordedStep {
  SolveStatus status = SolveStatus::Converged;  // of the step's last (Newton) solve
  int iterations = 0;                           // the inner optimizer's
  int polish_iterations = 0;                    // Newton's after it (0 where Newton solved the step)
  bool polished = false;                        // Newton moved the optimizer's result
  int exact_newton_steps = 0;                   // the direct-solve Newton steps kept after it
  double residual_acceleration = 0.0;           // at the recorded result [m/s^2]
  std::optional<StepStationarity> stationarity;  // with classify_steps
  int negative_eigenvalues = 0;                 // of H_FF (-1 singular) with classify_steps
  double repulsion_energy = 0.0;                // self-repulsion at the result [J]: > 0 where pairs act
  double solve_ms = 0.0;                        // the step's solves (optimizer, Newton, exact steps)
  bool released = false;                        // the handles were let go: every vertex free
};

struct RecordedRollout {
  ResolvedScene scene;
  RecordOptions options;  // how it was recorded (the backward pass re-simulates with them)
  // Per frame f = 0 .. frames - 1 (frame 0 the initial state): positions and velocities (with
  // checkpoints, empty off the checkpoint frames).
  std::vector<VecX> positions, velocities;
  // Per step s = 0 .. frames - 2, from frame s to s + 1: the acceleration (every dof, the handles'
  // prescribed; with checkpoints, empty) and the handles' targets at frame s + 1.
  std::vector<VecX> accelerations;
  std::vector<std::vector<Vec3>> handle_targets;
  std::vector<RecordedStep> steps;
  bool diverged = false;
  std::string divergence;
  double forward_ms = 0.0;  // the whole forward pass, solves and classification

  int frame_count() const { return static_cast<int>(positions.size()); }
  int step_count() const { return static_cast<int>(steps.size()); }
  bool empty() const { return positions.empty(); }
  int polished_steps() const;
  int unconverged_steps() const;                       // last solve not converged (is_converged)
  int steps_at(StepStationarity stationarity) const;   // with classify_steps
  std::size_t memory_bytes() const;                    // the states, accelerations and targets held
};

// The rollout of scene.frames frames, every step solved by Newton to options' tolerance.
RecordedRollout record_rollout(const ResolvedScene& scene, const RecordOptions& options = {},
                               const RolloutInputs& inputs = {});
// The same, every step solved by `optimizer` under `solve` and then polished by Newton.
RecordedRollout record_rollout(const ResolvedScene& scene, InnerOptimizer& optimizer, const InnerSolveOptions& solve,
                               const RecordOptions& options = {}, const RolloutInputs& inputs = {});

}  // namespace fnopt
