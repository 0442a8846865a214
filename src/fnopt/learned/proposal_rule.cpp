#include <fnopt/learned/proposal_rule.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

void LearnedParams::validate() const {
  require(min_rescale >= 0.0, "fnopt.min_rescale", "must not be negative");
  require(max_rescale >= 1.0, "fnopt.max_rescale", "must be at least 1");
  require_subspace_size(subspace, "fnopt.subspace");
  require(!pqn_direction || subspace > 0, "fnopt.pqn_direction", "needs the subspace step (subspace > 0)");
}

void require_subspace_size(int subspace, const std::string& field) {
  require(subspace >= 0 && subspace <= SecantSubspace::kMaxCapacity, field,
          "must be 0 to " + std::to_string(SecantSubspace::kMaxCapacity));
}

ProposalRule::ProposalRule(LearnedParams params)
    : params_(params), subspace_(std::clamp(params.subspace, 1, SecantSubspace::kMaxCapacity)) {
  params_.validate();
}

LearnedState ProposalRule::apply(StepProblem& problem, const torch::Tensor& gradient_samples,
                                 const LearnedStep& proposal, VecX& a, double& value, VecX& gradient) {
  torch::NoGradGuard no_grad;
  const Grid& grid = problem.grid();
  if (params_.safeguard || params_.line_search || params_.subspace > 0) {
    start_ = a;
    start_gradient_ = gradient;
  }
  add_coordinate_samples(proposal.delta, grid, acceleration_per_grid_unit(grid, problem.objective().dt()), a);
  const double start_value = value;
  value = problem.value_gradient(a, gradient);
  const double alpha = params_.subspace > 0  ? subspace_update(problem, a, value, gradient)
                       : params_.line_search ? secant_update(problem, a, value, gradient)
                                             : 1.0;
  LearnedState next{gradient_samples, alpha == 1.0 ? proposal.delta : proposal.delta * alpha,
                    alpha == 1.0 ? proposal.scale : (proposal.scale * alpha).clamp(kMinStepScale, kMaxStepScale)};
  if (params_.safeguard && !(value <= start_value)) {
    a.swap(start_);
    gradient.swap(start_gradient_);
    value = start_value;
    next.delta = torch::zeros_like(proposal.delta);
    next.scale = proposal.scale * 0.25;
  }
  return next;
}

void ProposalRule::add_pqn_direction(StepProblem& problem, const VecX& a, const VecX& gradient) {
  if (!params_.pqn_direction) return;
  PqnFactor& factor = pqn_factor_.prepare(problem);
  pqn_step_ = -gradient;
  factor.solve_in_place(pqn_step_);
  trial_ = a + pqn_step_;
  if (!std::isfinite(problem.value_gradient(trial_, gradient_change_))) return;
  gradient_change_ -= gradient;
  subspace_.push(pqn_step_, gradient_change_);
}

bool ProposalRule::take_trial_if_lower(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  const double trial_value = problem.value_gradient(trial_, trial_gradient_);
  if (!(trial_value < value)) return false;
  a.swap(trial_);
  gradient.swap(trial_gradient_);
  value = trial_value;
  return true;
}

double ProposalRule::secant_update(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  direction_ = a - start_;
  const double slope_before = start_gradient_.dot(direction_), slope_after = gradient.dot(direction_);
  // A descent direction along which L curves upward: the secant step is defined.
  if (!(slope_before < 0.0 && slope_after > slope_before && std::isfinite(value))) return 1.0;
  const double alpha =
      std::clamp(slope_before / (slope_before - slope_after), 1.0 / params_.max_rescale, params_.max_rescale);
  if (std::abs(alpha - 1.0) <= params_.min_rescale) return 1.0;
  trial_ = start_ + alpha * direction_;
  return take_trial_if_lower(problem, a, value, gradient) ? alpha : 1.0;
}

double ProposalRule::subspace_update(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  direction_ = a - start_;
  gradient_change_ = gradient - start_gradient_;
  if (!std::isfinite(value) || !subspace_.push(direction_, gradient_change_)) return 1.0;
  const SecantSubspace::Coefficients c = subspace_.minimiser(start_gradient_);
  subspace_.combine(c, trial_);
  if ((trial_ - direction_).norm() <= params_.min_rescale * direction_.norm()) return 1.0;
  trial_ += start_;
  if (!take_trial_if_lower(problem, a, value, gradient)) return 1.0;
  const double newest = c(c.size() - 1);
  return newest > 0.0 ? std::clamp(newest, 1.0 / params_.max_rescale, params_.max_rescale) : 1.0;
}

}  // namespace fnopt
