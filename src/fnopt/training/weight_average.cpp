#include <fnopt/training/weight_average.hpp>

#include <fnopt/util/error.hpp>

namespace fnopt {

WeightAverage::WeightAverage(const FNO2d& model) : average_(model->options) {
  for (auto& parameter : average_->parameters()) parameter.set_requires_grad(false);
  reset_to(model);
}

void WeightAverage::update(const FNO2d& model, double decay) {
  require(decay >= 0.0 && decay < 1.0, "weight average decay", "must lie in [0, 1)");
  torch::NoGradGuard no_grad;
  const auto trained = model->parameters();
  auto average = average_->parameters();
  for (std::size_t i = 0; i < average.size(); ++i) average[i].mul_(decay).add_(trained[i].detach(), 1.0 - decay);
}

void WeightAverage::reset_to(const FNO2d& model) {
  torch::NoGradGuard no_grad;
  const auto trained = model->parameters();
  auto average = average_->parameters();
  for (std::size_t i = 0; i < average.size(); ++i) average[i].copy_(trained[i]);
}

}  // namespace fnopt
