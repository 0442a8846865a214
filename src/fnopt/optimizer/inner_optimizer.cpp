#include <fnopt/optimizer/inner_optimizer.hpp>

#include <cmath>

namespace fnopt {
namespace {

// The no-penetration filter (docs/design.md §14): where the move from a_from to a leaves the
// feasible set after the fraction s, a = a_from + pullback s (a - a_from), with value and gradient
// there. Every method's iterate passes here, those without a line search (GD, Adam, L-BFGS with a
// fixed step, the learned ones) included. Returns whether it pulled a back.
bool keep_feasible(StepProblem& problem, const VecX& a_from, VecX& a, double& value, VecX& gradient) {
  const double fraction = problem.feasible_fraction(a_from, a);
  if (fraction >= 1.0) return false;
  a = a_from + problem.pullback() * fraction * (a - a_from);
  value = problem.value_gradient(a, gradient);
  return true;
}

}  // namespace

InnerSolveResult solve_step(InnerOptimizer& optimizer, StepProblem& problem, VecX& a,
                            const InnerSolveOptions& options) {
  InnerSolveResult result;
  VecX gradient;
  const bool contact = problem.has_contact();
  VecX a_before;  // the iterate before a move, kept only with obstacles
  if (contact) problem.make_start_feasible(a);
  double value = problem.value_gradient(a, gradient);
  result.initial_value = value;
  result.initial_gradient_norm = gradient.norm();
  result.gradient_norms.push_back(result.initial_gradient_norm);
  const double tolerance = options.relative_tolerance * result.initial_gradient_norm;
  optimizer.begin_step(problem, a, value, gradient);
  double gradient_norm = result.initial_gradient_norm;
  for (;;) {
    result.value = value;
    result.gradient_norm = gradient_norm;
    if (!std::isfinite(value) || !std::isfinite(gradient_norm) || !a.allFinite()) {
      result.status = SolveStatus::NonFinite;
      return result;
    }
    if ((options.relative_tolerance > 0.0 && gradient_norm <= tolerance) ||
        (options.acceleration_tolerance > 0.0 &&
         problem.objective().residual_acceleration(gradient) <= options.acceleration_tolerance)) {
      if (contact) a_before = a;
      if (result.iterations < options.max_iterations && optimizer.leave_stationary_point(problem, a, value, gradient)) {
        if (contact) keep_feasible(problem, a_before, a, value, gradient);
        ++result.iterations;
        gradient_norm = gradient.norm();
        result.gradient_norms.push_back(gradient_norm);
        continue;
      }
      result.status = SolveStatus::Converged;
      return result;
    }
    if (result.iterations >= options.max_iterations) {
      result.status = SolveStatus::IterationBudget;
      return result;
    }
    const bool filter = contact && !optimizer.filters_its_iterates();
    if (filter) a_before = a;
    auto stop = optimizer.iterate(problem, a, value, gradient);
    // A method that stopped on a non-finite value went into an obstacle: pulled back, it goes on.
    if (filter && keep_feasible(problem, a_before, a, value, gradient) && stop == SolveStatus::NonFinite &&
        std::isfinite(value))
      stop.reset();
    if (stop) {
      result.status = *stop;
      result.value = value;
      result.gradient_norm = gradient.norm();
      return result;
    }
    ++result.iterations;
    gradient_norm = gradient.norm();
    result.gradient_norms.push_back(gradient_norm);
  }
}

}  // namespace fnopt
