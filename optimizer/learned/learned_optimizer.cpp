#include "optimizer/learned/learned_optimizer.hpp"

#include "fno/fno_io.hpp"
#include "optimizer/learned/grid_tensor.hpp"

namespace fnopt {

LearnedOptimizer::LearnedOptimizer(const std::string& model_path)
    : LearnedOptimizer(
          [&] {
            check_learned_model(load_fno_options(model_path), model_path);
            return load_fno(model_path);
          }(),
          model_path) {}

LearnedOptimizer::LearnedOptimizer(FNO2d model, std::string model_name)
    : model_(std::move(model)), model_name_(std::move(model_name)) {
  check_learned_model(model_->options, model_name_);
  model_->eval();
}

std::string LearnedOptimizer::settings() const {
  const auto& o = model_->options;
  return "fnopt: model=" + model_name_ + " width=" + std::to_string(o.width()) + " layers=" +
         std::to_string(o.fourier_layers()) + " modes=" + std::to_string(o.modes_x()) + "x" +
         std::to_string(o.modes_y());
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
  // delta is in cell widths of position change: a changes by delta * h / dt^2.
  add_coordinate_samples(to_coordinate_layout(step.delta), grid, grid.spacing / (dt * dt), a);
  state_ = {g, step.delta, step.scale};
  value = problem.value_gradient(a, gradient);
  return std::nullopt;
}

}  // namespace fnopt
