#include <fnopt/baselines/gradient_descent.hpp>

#include <cmath>
#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt {

void GradientDescentParams::validate() const {
  require(std::isfinite(learning_rate) && learning_rate > 0.0, "gd.learning_rate", "must be positive");
  require(power_iterations >= 1 && power_iterations <= 1000, "gd.power_iterations", "must lie in [1, 1000]");
}

GradientDescentOptimizer::GradientDescentOptimizer(GradientDescentParams params) : params_(params) {
  params_.validate();
}

std::string GradientDescentOptimizer::settings() const {
  std::ostringstream out;
  out << "gd: learning_rate=" << params_.learning_rate
      << (params_.curvature_scaled ? " (x 1/lambda_max, mass metric)" : " (mass metric)")
      << " power_iterations=" << params_.power_iterations;
  return out.str();
}

void GradientDescentOptimizer::begin(SmoothProblem& problem, const VecX& x, double, const VecX& gradient) {
  if (curvature_ > 0.0) return;
  curvature_ = params_.curvature_scaled ? estimate_max_curvature(problem, x, gradient, params_.power_iterations) : 1.0;
}

std::optional<SolveStatus> GradientDescentOptimizer::step(SmoothProblem& problem, VecX& x, double& value,
                                                          VecX& gradient) {
  if (!(curvature_ > 0.0)) begin(problem, x, value, gradient);
  x.noalias() -= (params_.learning_rate / curvature_) * problem.inverse_metric().cwiseProduct(gradient);
  value = problem.value_gradient(x, gradient);
  return std::nullopt;
}

}  // namespace fnopt
