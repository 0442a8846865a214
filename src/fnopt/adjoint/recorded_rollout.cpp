#include <fnopt/adjoint/recorded_rollout.hpp>

#include <chrono>
#include <cmath>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/simulation/simulator.hpp>
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

  NewtonOptimizer newton;
  const InnerSolveOptions exact{options.max_newton_iterations, 0.0, options.acceleration_tolerance};
  RolloutOptions rollout_options;
  rollout_options.divergence_strain = options.divergence_strain;
  Simulator simulator(scene, newton, rollout_options);
  simulator.set_state(inputs.initial_positions.value_or(scene.grid.rest_positions()),
                      inputs.initial_velocities.value_or(VecX::Zero(scene.grid.dof_count())), 0);
  StepLinearization linearization(scene);

  RecordedRollout out;
  out.scene = scene;
  out.positions.push_back(simulator.positions());
  out.velocities.push_back(simulator.velocities());
  for (int s = 0; s < steps; ++s) {
    const std::vector<Vec3> targets =
        inputs.handle_targets ? (*inputs.handle_targets)[s] : simulator.trajectory_targets((s + 1) * scene.scene.dt);
    const VecX x = simulator.positions(), v = simulator.velocities();
    VecX a;
    StepProblem& problem = simulator.prepare_step(a, targets);
    if (inputs.start_accelerations)
      for (int k = 0; k < scene.grid.vertex_count(); ++k)
        if (problem.dirichlet().free_index()[k] >= 0) a.segment<3>(3 * k) = (*inputs.start_accelerations)[s].segment<3>(3 * k);
    RecordedStep step;
    const auto solve_begin = std::chrono::steady_clock::now();
    if (optimizer) {
      step.iterations = solve_step(*optimizer, problem, a, solve).iterations;
      const VecX solved = a;
      const InnerSolveResult polish = solve_step(newton, problem, a, exact);
      step.status = polish.status;
      step.polish_iterations = polish.iterations;
      step.polished = a != solved;
    } else {
      const InnerSolveResult result = solve_step(newton, problem, a, exact);
      step.status = result.status;
      step.iterations = result.iterations;
    }
    VecX gradient, correction;
    problem.value_gradient(a, gradient);
    step.residual_acceleration = problem.objective().residual_acceleration(gradient);
    // Newton's last iterates come from CG, to a forcing tolerance: finish with exact Newton steps,
    // a direct solve with H_FF each, for as long as they lower the residual.
    // `at_result`: the last linearisation is at the step's result (a step was refused), so the
    // classification below needs no factorisation of its own.
    std::optional<StepStationarity> at_result;
    for (int i = 0; i < options.exact_newton_steps; ++i) {
      const StepStationarity stationarity = linearization.linearize(x, v, a);
      if (stationarity == StepStationarity::Singular) {
        at_result = stationarity;
        break;
      }
      linearization.solve(gradient, correction);
      const VecX previous = a;
      a -= correction;
      problem.value_gradient(a, gradient);
      const double residual = problem.objective().residual_acceleration(gradient);
      if (!(residual < step.residual_acceleration)) {
        a = previous;
        problem.value_gradient(a, gradient);
        at_result = stationarity;
        break;
      }
      step.residual_acceleration = residual;
      ++step.exact_newton_steps;
    }
    step.solve_ms = elapsed_ms(solve_begin);
    if (const RepulsionTerm* repulsion = problem.objective().repulsion()) {
      VecX x_next;
      problem.objective().trial_positions(a, x_next);
      step.repulsion_energy = repulsion->energy(x_next);
    }
    simulator.commit(a);
    if (simulator.diverged()) {
      out.diverged = true;
      out.divergence = simulator.divergence();
      break;
    }
    if (options.classify_steps) {
      step.stationarity = at_result ? *at_result : linearization.linearize(x, v, a);
      step.negative_eigenvalues = linearization.negative_eigenvalues();
    }
    out.accelerations.push_back(a);  // its handle dofs hold the prescription (prepare_step)
    out.handle_targets.push_back(targets);
    out.steps.push_back(step);
    out.positions.push_back(simulator.positions());
    out.velocities.push_back(simulator.velocities());
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
