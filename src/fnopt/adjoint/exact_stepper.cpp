#include <fnopt/adjoint/exact_stepper.hpp>

#include <chrono>

#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

NewtonParams newton_params(bool reproducible) {
  NewtonParams params;
  params.reuse_factor_across_steps = !reproducible;
  return params;
}

RolloutOptions rollout_options(const RecordOptions& options) {
  RolloutOptions rollout;
  rollout.divergence_strain = options.divergence_strain;
  return rollout;
}

}  // namespace

ExactStepper::ExactStepper(const ResolvedScene& scene, const RecordOptions& options, const VecX& x, const VecX& v,
                           int steps, bool reproducible)
    : options_(validated(options)),
      newton_(newton_params(reproducible)),
      simulator_(scene, newton_, rollout_options(options)),
      linearization_(scene) {
  simulator_.set_state(x, v, steps);
}

RecordedStep ExactStepper::step(const std::vector<Vec3>& targets, const VecX* start, InnerOptimizer* optimizer,
                                const InnerSolveOptions& solve, VecX& a) {
  const auto begin = std::chrono::steady_clock::now();
  const InnerSolveOptions exact{options_.max_newton_iterations, 0.0, options_.acceleration_tolerance};
  const VecX x = simulator_.positions(), v = simulator_.velocities();
  const double time = simulator_.time();
  StepProblem& problem = simulator_.prepare_step(a, targets);
  linearization_.set_released(simulator_.handles_released());
  const std::vector<int>& free_index = problem.dirichlet().free_index();
  if (start)
    for (std::size_t k = 0; k < free_index.size(); ++k)
      if (free_index[k] >= 0) a.segment<3>(3 * k) = start->segment<3>(3 * k);

  RecordedStep step;
  step.released = simulator_.handles_released();
  if (optimizer) {
    step.iterations = solve_step(*optimizer, problem, a, solve).iterations;
    const VecX solved = a;
    const InnerSolveResult polish = solve_step(newton_, problem, a, exact);
    step.status = polish.status;
    step.polish_iterations = polish.iterations;
    step.polished = a != solved;
  } else {
    const InnerSolveResult result = solve_step(newton_, problem, a, exact);
    step.status = result.status;
    step.iterations = result.iterations;
  }
  VecX gradient, correction;
  problem.value_gradient(a, gradient);
  step.residual_acceleration = problem.objective().residual_acceleration(gradient);
  // Newton's last iterates come from CG, to a forcing tolerance: finish with exact Newton steps, a
  // direct solve with H_FF each, for as long as they lower the residual. `at_result`: the last
  // linearisation is at the step's result (a step was refused), so the classification below
  // needs no factorisation of its own.
  std::optional<StepStationarity> at_result;
  for (int i = 0; i < options_.exact_newton_steps; ++i) {
    const StepStationarity stationarity = linearization_.linearize(x, v, a, time);
    if (stationarity == StepStationarity::Singular) {
      at_result = stationarity;
      break;
    }
    linearization_.solve(gradient, correction);
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
  step.solve_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  if (const RepulsionTerm* repulsion = problem.objective().repulsion()) {
    VecX x_next;
    problem.objective().trial_positions(a, x_next);
    step.repulsion_energy = repulsion->energy(x_next);
  }
  simulator_.commit(a);
  if (!simulator_.diverged() && options_.classify_steps) {
    step.stationarity = at_result ? *at_result : linearization_.linearize(x, v, a, time);
    step.negative_eigenvalues = linearization_.negative_eigenvalues();
  }
  return step;
}

}  // namespace fnopt
