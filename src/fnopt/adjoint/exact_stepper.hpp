#pragma once
// One exact backward-Euler step after another (docs/design.md §15): the recorded forward pass's
// stepping, and the backward pass's re-simulation of a checkpointed segment. Each step is solved by
// Newton to RecordOptions' residual (or by an inner optimizer and polished by Newton), finished by
// exact Newton steps a -= H_FF^-1 g_F (direct solves, each kept only if it lowers the residual),
// and classified at its result.
#include <optional>
#include <string>
#include <vector>

#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/step_linearization.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/simulation/simulator.hpp>

namespace fnopt {

class ExactStepper {
 public:
  // Starts at (x, v) at `steps` steps done. With `reproducible`, Newton factorises its
  // preconditioner afresh at every step (NewtonParams::reuse_factor_across_steps off), so that a
  // step's solve depends on its state and targets alone, and a segment re-simulated from a
  // checkpoint takes the same path.
  ExactStepper(const ResolvedScene& scene, const RecordOptions& options, const VecX& x, const VecX& v, int steps,
               bool reproducible);
  ExactStepper(const ExactStepper&) = delete;
  ExactStepper& operator=(const ExactStepper&) = delete;

  // The scene's trajectory at time t.
  std::vector<Vec3> trajectory_targets(double t) const { return simulator_.trajectory_targets(t); }

  // One step with the handles at `targets`, from the first iterate `start` (its free dofs; null:
  // 0), solved by `optimizer` under `solve` and polished (null: Newton alone). Writes the step's
  // acceleration (every dof, the handles' prescribed) and returns its record; after a divergence
  // (diverged()) the state stays the one before.
  RecordedStep step(const std::vector<Vec3>& targets, const VecX* start, InnerOptimizer* optimizer,
                    const InnerSolveOptions& solve, VecX& acceleration);

  const VecX& positions() const { return simulator_.positions(); }
  const VecX& velocities() const { return simulator_.velocities(); }
  bool diverged() const { return simulator_.diverged(); }
  const std::string& divergence() const { return simulator_.divergence(); }

 private:
  RecordOptions options_;
  NewtonOptimizer newton_;
  Simulator simulator_;
  StepLinearization linearization_;
};

}  // namespace fnopt
