#include <fnopt/optimizer/inner_optimizer.hpp>

#include <cmath>

namespace fnopt {

InnerSolveResult solve_step(InnerOptimizer& optimizer, StepProblem& problem, VecX& a,
                            const InnerSolveOptions& options) {
  InnerSolveResult result;
  VecX gradient;
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
      if (result.iterations < options.max_iterations && optimizer.leave_stationary_point(problem, a, value, gradient)) {
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
    if (const auto stop = optimizer.iterate(problem, a, value, gradient)) {
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
