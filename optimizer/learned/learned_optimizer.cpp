#include "optimizer/learned/learned_optimizer.hpp"

#include "cloth/grid_units.hpp"
#include "fno/fno_io.hpp"
#include "optimizer/learned/grid_tensor.hpp"

namespace fnopt {

LearnedOptimizer::LearnedOptimizer(const std::string& model_path, bool safeguard)
    : LearnedOptimizer(
          [&] {
            check_learned_model(load_fno_options(model_path), model_path);
            return load_fno(model_path);
          }(),
          model_path, safeguard) {}

LearnedOptimizer::LearnedOptimizer(FNO2d model, std::string model_name, bool safeguard)
    : model_(std::move(model)), model_name_(std::move(model_name)), safeguard_(safeguard) {
  check_learned_model(model_->options, model_name_);
  model_->eval();
}

std::string LearnedOptimizer::settings() const {
  const auto& o = model_->options;
  return "fnopt: model=" + model_name_ + " width=" + std::to_string(o.width()) + " layers=" +
         std::to_string(o.fourier_layers()) + " modes=" + std::to_string(o.modes_x()) + "x" +
         std::to_string(o.modes_y()) + (o.in_channels() == 9 ? " combined" : "") +
         " safeguard=" + (safeguard_ ? "on" : "off");
}

void LearnedOptimizer::begin_step(StepProblem& problem, const VecX&, double, const VecX&) {
  const Grid& grid = problem.grid();
  if (mask_owner_ != &problem.dirichlet() || !mask_.defined() || mask_.size(2) != grid.rows ||
      mask_.size(3) != grid.cols) {
    mask_ = free_mask(problem.dirichlet(), grid);
    mask_owner_ = &problem.dirichlet();
    state_.scale = torch::Tensor();
  }
  state_.gradient = torch::Tensor();
  state_.delta = torch::Tensor();
}

std::optional<SolveStatus> LearnedOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  torch::NoGradGuard no_grad;
  const Grid& grid = problem.grid();
  const double dt = problem.objective().dt();
  const torch::Tensor g = to_model_layout(to_coordinate_samples(gradient, grid), samples_per_environment(model_->options));
  const LearnedStep step = learned_step(model_, g, state_, mask_);
  if (safeguard_) {
    previous_a_ = a;
    previous_gradient_ = gradient;
  }
  add_coordinate_samples(to_coordinate_layout(step.delta), grid, acceleration_per_grid_unit(grid, dt), a);
  state_ = {g, step.delta, step.scale};
  const double previous_value = value;
  value = problem.value_gradient(a, gradient);
  if (safeguard_ && !(value <= previous_value)) {
    a.swap(previous_a_);
    gradient.swap(previous_gradient_);
    value = previous_value;
    state_.delta = torch::zeros_like(step.delta);
    state_.scale = step.scale * 0.25;
  }
  return std::nullopt;
}

}  // namespace fnopt
