#include <fnopt/baselines/adam.hpp>

#include <cmath>
#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt {

void AdamParams::validate() const {
  require(std::isfinite(learning_rate) && learning_rate > 0.0, "adam.learning_rate", "must be positive");
  require(beta1 >= 0.0 && beta1 < 1.0, "adam.beta1", "must lie in [0, 1)");
  require(beta2 >= 0.0 && beta2 < 1.0, "adam.beta2", "must lie in [0, 1)");
  require(std::isfinite(epsilon) && epsilon > 0.0, "adam.epsilon", "must be positive");
}

AdamOptimizer::AdamOptimizer(AdamParams params) : params_(params) { params_.validate(); }

std::string AdamOptimizer::settings() const {
  std::ostringstream out;
  out << "adam: learning_rate=" << params_.learning_rate << " (cell widths per step^2) beta1=" << params_.beta1
      << " beta2=" << params_.beta2 << " epsilon=" << params_.epsilon << " (mass metric)";
  return out.str();
}

void AdamOptimizer::begin(SmoothProblem&, const VecX& x, double, const VecX&) {
  first_moment_.setZero(x.size());
  second_moment_.setZero(x.size());
  iteration_ = 0;
  beta1_power_ = beta2_power_ = 1.0;
}

std::optional<SolveStatus> AdamOptimizer::step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) {
  if (first_moment_.size() != x.size()) begin(problem, x, value, gradient);
  ++iteration_;
  beta1_power_ *= params_.beta1;
  beta2_power_ *= params_.beta2;
  preconditioned_ = problem.inverse_metric().cwiseProduct(gradient);
  first_moment_ = params_.beta1 * first_moment_ + (1.0 - params_.beta1) * preconditioned_;
  second_moment_ = params_.beta2 * second_moment_ + (1.0 - params_.beta2) * preconditioned_.cwiseAbs2();
  const double step = params_.learning_rate * problem.step_unit();
  const double correction1 = 1.0 / (1.0 - beta1_power_);
  const double correction2 = 1.0 / (1.0 - beta2_power_);
  x.array() -=
      step * (correction1 * first_moment_.array()) / ((correction2 * second_moment_.array()).sqrt() + params_.epsilon);
  value = problem.value_gradient(x, gradient);
  return std::nullopt;
}

}  // namespace fnopt
