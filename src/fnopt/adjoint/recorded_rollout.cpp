#include <fnopt/adjoint/recorded_rollout.hpp>

#include <chrono>
#include <cmath>

#include <fnopt/adjoint/exact_stepper.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// Runs the steps; `optimizer` null: Newton alone.
RecordedRollout record(const ResolvedScene& scene, InnerOptimizer* optimizer, const InnerSolveOptions& solve,
                       const RecordOptions& options, const RolloutInputs& inputs) {
  options.validate();
  const auto begin = std::chrono::steady_clock::now();
  const int steps = scene.scene.frames - 1;
  if (inputs.handle_targets)
    require(static_cast<int>(inputs.handle_targets->size()) == steps, "handle targets",
            "expected " + std::to_string(steps) + " rows (one per step), got " +
                std::to_string(inputs.handle_targets->size()));
  if (inputs.start_accelerations) {
    bool ok = static_cast<int>(inputs.start_accelerations->size()) == steps;
    for (const VecX& a : *inputs.start_accelerations) ok = ok && a.size() == scene.grid.dof_count();
    require(ok, "start accelerations",
            "expected " + std::to_string(steps) + " rows (one per step) of " + std::to_string(scene.grid.dof_count()) +
                " values");
  }
  const int interval = options.checkpoint_interval;
  if (interval > 0) {
    require(!optimizer, "checkpoint_interval",
            "a checkpointed rollout is re-simulated by Newton alone: record it without another optimizer");
    require(!inputs.start_accelerations, "checkpoint_interval",
            "a checkpointed rollout is re-simulated from a = 0: record it without start accelerations");
  }

  RecordedRollout out;
  out.scene = scene;
  out.options = options;
  ExactStepper stepper(scene, options, inputs.initial_positions.value_or(scene.start_positions()),
                       inputs.initial_velocities.value_or(VecX::Zero(scene.grid.dof_count())), 0, interval > 0);
  out.positions.push_back(stepper.positions());
  out.velocities.push_back(stepper.velocities());
  for (int s = 0; s < steps; ++s) {
    const std::vector<Vec3> targets =
        inputs.handle_targets ? (*inputs.handle_targets)[s] : stepper.trajectory_targets((s + 1) * scene.scene.dt);
    VecX a;
    const RecordedStep step = stepper.step(
        targets, inputs.start_accelerations ? &(*inputs.start_accelerations)[s] : nullptr, optimizer, solve, a);
    if (stepper.diverged()) {
      out.diverged = true;
      out.divergence = stepper.divergence();
      break;
    }
    const bool checkpoint = interval > 0 && (s + 1) % interval == 0;
    out.accelerations.push_back(interval > 0 ? VecX() : a);  // its handle dofs hold the prescription
    out.handle_targets.push_back(targets);
    out.steps.push_back(step);
    out.positions.push_back(stepper.positions());
    out.velocities.push_back(interval == 0 || checkpoint ? stepper.velocities() : VecX());
  }
  out.forward_ms = elapsed_ms(begin);
  return out;
}

}  // namespace

void RecordOptions::validate() const {
  require(std::isfinite(acceleration_tolerance) && acceleration_tolerance > 0.0, "acceleration_tolerance",
          "must be positive (m/s^2)");
  require(max_newton_iterations >= 1, "max_newton_iterations", "must be at least 1");
  require(exact_newton_steps >= 0, "exact_newton_steps", "must be zero or more");
  require(std::isfinite(divergence_strain) && divergence_strain > 0.0, "divergence_strain", "must be positive");
  require(checkpoint_interval >= 0, "checkpoint_interval", "must be zero (every state kept) or more");
}

int RecordedRollout::polished_steps() const {
  int count = 0;
  for (const RecordedStep& step : steps) count += step.polished;
  return count;
}

int RecordedRollout::unconverged_steps() const {
  int count = 0;
  for (const RecordedStep& step : steps) count += !is_converged(step.status);
  return count;
}

int RecordedRollout::steps_at(StepStationarity stationarity) const {
  int count = 0;
  for (const RecordedStep& step : steps) count += step.stationarity == stationarity;
  return count;
}

std::size_t RecordedRollout::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto* states : {&positions, &velocities, &accelerations})
    for (const VecX& state : *states) bytes += state.size() * sizeof(double);
  for (const auto& targets : handle_targets) bytes += targets.size() * sizeof(Vec3);
  return bytes;
}

RecordedRollout record_rollout(const ResolvedScene& scene, const RecordOptions& options, const RolloutInputs& inputs) {
  return record(scene, nullptr, {}, options, inputs);
}

RecordedRollout record_rollout(const ResolvedScene& scene, InnerOptimizer& optimizer, const InnerSolveOptions& solve,
                               const RecordOptions& options, const RolloutInputs& inputs) {
  return record(scene, &optimizer, solve, options, inputs);
}

}  // namespace fnopt
