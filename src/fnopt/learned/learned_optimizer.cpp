#include <fnopt/learned/learned_optimizer.hpp>

#include <fnopt/learned/grid_tensor.hpp>

namespace fnopt {

LearnedOptimizer::LearnedOptimizer(const std::string& model_path, LearnedParams params, std::string method_name)
    : LearnedOptimizer(load_learned_model(model_path), model_path, params) {
  method_name_ = std::move(method_name);
}

LearnedOptimizer::LearnedOptimizer(FNO2d model, std::string model_name, LearnedParams params)
    : model_(std::move(model)), model_name_(std::move(model_name)), rule_(with_model_inputs(params, model_)) {
  model_->eval();
}

LearnedParams LearnedOptimizer::with_model_inputs(LearnedParams params, const FNO2d& model) const {
  check_learned_model(model->options, model_name_);
  params.pqn_input = takes_pqn_direction(model->options);
  return params;
}

std::string LearnedOptimizer::name() const {
  if (!method_name_.empty()) return method_name_;
  const LearnedParams& p = rule_.params();
  if (p.subspace > 0) return p.pqn_direction ? "fnopt" : "fnopt-ss";
  return p.line_search ? "fnopt-ls" : "fnopt-plain";
}

std::string LearnedOptimizer::settings() const {
  const auto& o = model_->options;
  const LearnedParams& p = rule_.params();
  return name() + ": model=" + model_name_ + " width=" + std::to_string(o.width()) +
         " layers=" + std::to_string(o.fourier_layers()) + " modes=" + std::to_string(o.modes_x()) + "x" +
         std::to_string(o.modes_y()) + (samples_per_environment(o) == 1 ? " combined" : "") +
         (takes_pqn_direction(o) ? " pqn_input" : "") + (takes_grid_size(o) ? " grid_size_input" : "") +
         " safeguard=" + (p.safeguard ? "on" : "off") + " line_search=" + (p.line_search ? "on" : "off") +
         (p.subspace > 0 ? " subspace=" + std::to_string(p.subspace) + (p.carry_subspace ? " carried" : "") +
                               (p.pqn_direction ? " pqn_direction=isotropic" : "")
                         : "");
}

void LearnedOptimizer::begin_step(StepProblem& problem, const VecX&, double, const VecX&) {
  const Grid& grid = problem.grid();
  if (mask_owner_ != &problem.dirichlet() || !mask_.defined() || mask_.size(2) != grid.rows ||
      mask_.size(3) != grid.cols) {
    mask_ = free_mask(problem.dirichlet(), grid);
    mask_owner_ = &problem.dirichlet();
    state_.scale = torch::Tensor();
    rule_.pairs().clear();
  }
  state_.gradient = torch::Tensor();
  state_.delta = torch::Tensor();
  const LearnedParams& p = rule_.params();
  if (!p.carry_subspace || !continues_previous_step(problem.objective())) rule_.pairs().clear();
  if (p.subspace > 0) previous_start_ = problem.objective().start_positions();
}

bool LearnedOptimizer::continues_previous_step(const BackwardEulerObjective& objective) const {
  const VecX& x = objective.start_positions();
  if (previous_start_.size() != x.size()) return false;
  // Backward Euler advanced the previous step's start by x_{t+1} = x_t + dt v_{t+1}.
  const double mismatch =
      (x - objective.dt() * objective.start_velocities() - previous_start_).lpNorm<Eigen::Infinity>();
  return mismatch <= kContinuationTolerance * (1.0 + x.lpNorm<Eigen::Infinity>());
}

std::optional<SolveStatus> LearnedOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  torch::NoGradGuard no_grad;
  rule_.add_pqn_direction(problem, a, gradient);
  const int k = samples_per_environment(model_->options);
  const torch::Tensor g = to_model_layout(to_coordinate_samples(gradient, problem.grid()), k);
  const torch::Tensor pqn =
      rule_.params().pqn_input ? to_model_layout(rule_.pqn_step_samples(problem), k) : torch::Tensor();
  const LearnedStep proposal = learned_step(model_, g, state_, mask_, pqn);
  state_ = rule_.apply(problem, g, proposal, a, value, gradient);
  return std::nullopt;
}

}  // namespace fnopt
