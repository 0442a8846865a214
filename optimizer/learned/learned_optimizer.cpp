#include "optimizer/learned/learned_optimizer.hpp"

#include <algorithm>
#include <cmath>

#include "cloth/grid_units.hpp"
#include "fno/fno_io.hpp"
#include "optimizer/learned/grid_tensor.hpp"
#include "util/error.hpp"

namespace fnopt {

void LearnedParams::validate() const {
  require(min_rescale >= 0.0, "fnopt.min_rescale", "must not be negative");
  require(max_rescale >= 1.0, "fnopt.max_rescale", "must be at least 1");
  require(subspace >= 0 && subspace <= SecantSubspace::kMaxCapacity, "fnopt.subspace",
          "must be 0 to " + std::to_string(SecantSubspace::kMaxCapacity));
}

LearnedOptimizer::LearnedOptimizer(const std::string& model_path, LearnedParams params)
    : LearnedOptimizer(
          [&] {
            check_learned_model(load_fno_options(model_path), model_path);
            return load_fno(model_path);
          }(),
          model_path, params) {}

LearnedOptimizer::LearnedOptimizer(FNO2d model, std::string model_name, LearnedParams params)
    : model_(std::move(model)),
      model_name_(std::move(model_name)),
      params_(params),
      subspace_(std::clamp(params.subspace, 1, SecantSubspace::kMaxCapacity)) {
  params_.validate();
  check_learned_model(model_->options, model_name_);
  model_->eval();
}

std::string LearnedOptimizer::name() const {
  if (params_.subspace > 0) return "fnopt-ss";
  return params_.line_search ? "fnopt-ls" : "fnopt";
}

std::string LearnedOptimizer::settings() const {
  const auto& o = model_->options;
  return name() + ": model=" + model_name_ + " width=" + std::to_string(o.width()) + " layers=" +
         std::to_string(o.fourier_layers()) + " modes=" + std::to_string(o.modes_x()) + "x" +
         std::to_string(o.modes_y()) + (o.in_channels() == 9 ? " combined" : "") +
         " safeguard=" + (params_.safeguard ? "on" : "off") + " line_search=" + (params_.line_search ? "on" : "off") +
         (params_.subspace > 0 ? " subspace=" + std::to_string(params_.subspace) +
                                        (params_.carry_subspace ? " carried" : "")
                                  : "");
}

void LearnedOptimizer::begin_step(StepProblem& problem, const VecX&, double, const VecX&) {
  const Grid& grid = problem.grid();
  if (mask_owner_ != &problem.dirichlet() || !mask_.defined() || mask_.size(2) != grid.rows ||
      mask_.size(3) != grid.cols) {
    mask_ = free_mask(problem.dirichlet(), grid);
    mask_owner_ = &problem.dirichlet();
    state_.scale = torch::Tensor();
    subspace_.clear();
  }
  state_.gradient = torch::Tensor();
  state_.delta = torch::Tensor();
  if (!params_.carry_subspace || !continues_previous_step(problem.objective())) subspace_.clear();
  if (params_.subspace > 0) previous_start_ = problem.objective().start_positions();
}

bool LearnedOptimizer::continues_previous_step(const BackwardEulerObjective& objective) const {
  const VecX& x = objective.start_positions();
  if (previous_start_.size() != x.size()) return false;
  // Backward Euler advanced the previous step's start by x_{t+1} = x_t + dt v_{t+1}.
  const double mismatch = (x - objective.dt() * objective.start_velocities() - previous_start_).lpNorm<Eigen::Infinity>();
  return mismatch <= kContinuationTolerance * (1.0 + x.lpNorm<Eigen::Infinity>());
}

bool LearnedOptimizer::take_trial_if_lower(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  const double trial_value = problem.value_gradient(trial_, trial_gradient_);
  if (!(trial_value < value)) return false;
  a.swap(trial_);
  gradient.swap(trial_gradient_);
  value = trial_value;
  return true;
}

double LearnedOptimizer::rescale_update(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  direction_ = a - previous_a_;
  const double slope_before = previous_gradient_.dot(direction_), slope_after = gradient.dot(direction_);
  // A descent direction along which L curves upward: the secant step is defined.
  if (!(slope_before < 0.0 && slope_after > slope_before && std::isfinite(value))) return 1.0;
  const double alpha = std::clamp(slope_before / (slope_before - slope_after), 1.0 / params_.max_rescale,
                                  params_.max_rescale);
  if (std::abs(alpha - 1.0) <= params_.min_rescale) return 1.0;
  trial_ = previous_a_ + alpha * direction_;
  return take_trial_if_lower(problem, a, value, gradient) ? alpha : 1.0;
}

double LearnedOptimizer::subspace_update(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  direction_ = a - previous_a_;
  gradient_change_ = gradient - previous_gradient_;
  if (!std::isfinite(value) || !subspace_.push(direction_, gradient_change_)) return 1.0;
  const SecantSubspace::Coefficients c = subspace_.minimiser(previous_gradient_);
  subspace_.combine(c, trial_);
  if ((trial_ - direction_).norm() <= params_.min_rescale * direction_.norm()) return 1.0;
  trial_ += previous_a_;
  if (!take_trial_if_lower(problem, a, value, gradient)) return 1.0;
  const double newest = c(c.size() - 1);
  return newest > 0.0 ? std::clamp(newest, 1.0 / params_.max_rescale, params_.max_rescale) : 1.0;
}

std::optional<SolveStatus> LearnedOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  torch::NoGradGuard no_grad;
  const Grid& grid = problem.grid();
  const double dt = problem.objective().dt();
  const torch::Tensor g = to_model_layout(to_coordinate_samples(gradient, grid), samples_per_environment(model_->options));
  const LearnedStep step = learned_step(model_, g, state_, mask_);
  if (params_.safeguard || params_.line_search || params_.subspace > 0) {
    previous_a_ = a;
    previous_gradient_ = gradient;
  }
  add_coordinate_samples(to_coordinate_layout(step.delta), grid, acceleration_per_grid_unit(grid, dt), a);
  const double previous_value = value;
  value = problem.value_gradient(a, gradient);
  const double alpha = params_.subspace > 0 ? subspace_update(problem, a, value, gradient)
                       : params_.line_search ? rescale_update(problem, a, value, gradient)
                                             : 1.0;
  state_ = {g, alpha == 1.0 ? step.delta : step.delta * alpha,
            alpha == 1.0 ? step.scale : (step.scale * alpha).clamp(kMinStepScale, kMaxStepScale)};
  if (params_.safeguard && !(value <= previous_value)) {
    a.swap(previous_a_);
    gradient.swap(previous_gradient_);
    value = previous_value;
    state_.delta = torch::zeros_like(step.delta);
    state_.scale = step.scale * 0.25;
  }
  return std::nullopt;
}

}  // namespace fnopt
