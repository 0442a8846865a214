#include <fnopt/baselines/first_order.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <fnopt/cloth/grid_units.hpp>

namespace fnopt {

ClothSmoothProblem::ClothSmoothProblem(StepProblem& problem) : problem_(&problem) {
  const BackwardEulerObjective& objective = problem.objective();
  const double dt = objective.dt();
  const VecX& masses = objective.masses();
  inverse_metric_.resize(3 * masses.size());
  for (Eigen::Index k = 0; k < masses.size(); ++k)
    inverse_metric_.segment<3>(3 * k).setConstant(1.0 / (dt * dt * masses[k]));
  step_unit_ = acceleration_per_grid_unit(problem.grid(), dt);
}

void FirstOrderOptimizer::begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) {
  const BackwardEulerObjective* objective = &problem.objective();
  if (!cloth_ || cloth_problem_ != &problem || cloth_objective_ != objective ||
      cloth_dofs_ != problem.grid().dof_count() || cloth_dt_ != objective->dt()) {
    cloth_.emplace(problem);
    cloth_problem_ = &problem;
    cloth_objective_ = objective;
    cloth_dofs_ = problem.grid().dof_count();
    cloth_dt_ = objective->dt();
    on_new_problem();
  }
  begin(*cloth_, a, value, gradient);
}

std::optional<SolveStatus> FirstOrderOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  if (!cloth_ || cloth_problem_ != &problem) begin_step(problem, a, value, gradient);
  return step(*cloth_, a, value, gradient);
}

double estimate_max_curvature(SmoothProblem& problem, const VecX& x, const VecX& gradient, int iterations) {
  const VecX& inverse_metric = problem.inverse_metric();
  // A fixed pseudo-random start (every eigenvector has a component in it).
  std::mt19937_64 random(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  VecX v(x.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = uniform(random);
  VecX trial, trial_gradient, product;
  double lambda = 1e-12;
  const double scale = 1e-6 * (1.0 + x.cwiseAbs().maxCoeff());
  for (int k = 0; k < iterations; ++k) {
    const double v_max = v.cwiseAbs().maxCoeff();
    if (!(v_max > 0.0) || !std::isfinite(v_max)) break;
    const double epsilon = scale / v_max;
    trial = x + epsilon * v;
    problem.value_gradient(trial, trial_gradient);
    product = (trial_gradient - gradient) / epsilon;  // H v
    // Rayleigh quotient of P^-1 H in the P inner product: v.Hv / v.Pv.
    const double p_norm2 = v.cwiseQuotient(inverse_metric).dot(v);
    if (!(p_norm2 > 0.0)) break;
    const double rayleigh = v.dot(product) / p_norm2;
    if (std::isfinite(rayleigh)) lambda = std::max(lambda, rayleigh);
    v = inverse_metric.cwiseProduct(product);
  }
  return lambda;
}

}  // namespace fnopt
