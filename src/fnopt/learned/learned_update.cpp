#include <fnopt/learned/learned_update.hpp>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// 10 tanh(x / (10 sigma)) with sigma = ||x||/sqrt(RC) per sample (zero stays zero).
torch::Tensor soft_normalize(const torch::Tensor& x) {
  const auto sigma = x.pow(2).mean({1, 2, 3}, /*keepdim=*/true).sqrt().clamp_min(1e-30);
  return 10.0 * torch::tanh(x / (10.0 * sigma));
}

}  // namespace

int samples_per_environment(const FNO2dOptions& options) { return options.in_channels() >= 9 ? 1 : 3; }

bool takes_pqn_direction(const FNO2dOptions& options) {
  return options.in_channels() == 4 || options.in_channels() == 12;
}

torch::Tensor to_model_layout(const torch::Tensor& coordinate_samples, int samples_per_environment) {
  if (samples_per_environment == 3) return coordinate_samples;
  return coordinate_samples.view({1, 3, coordinate_samples.size(2), coordinate_samples.size(3)});
}

torch::Tensor to_coordinate_layout(const torch::Tensor& model_samples) {
  return model_samples.reshape({3, 1, model_samples.size(2), model_samples.size(3)});
}

torch::Tensor learned_inputs(const torch::Tensor& gradient, const LearnedState& state,
                             const torch::Tensor& pqn_direction) {
  const auto sigma_g = gradient.pow(2).mean({1, 2, 3}, true).sqrt().clamp_min(1e-30);
  const auto g_hat = 10.0 * torch::tanh(gradient / (10.0 * sigma_g));
  const auto g_prev =
      state.gradient.defined() ? 10.0 * torch::tanh(state.gradient / (10.0 * sigma_g)) : torch::zeros_like(gradient);
  const auto d_prev = state.delta.defined() ? soft_normalize(state.delta) : torch::zeros_like(gradient);
  if (!pqn_direction.defined()) return torch::cat({g_hat, g_prev, d_prev}, 1).detach();
  return torch::cat({g_hat, g_prev, d_prev, soft_normalize(pqn_direction)}, 1).detach();
}

LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask, const torch::Tensor& pqn_direction) {
  require(takes_pqn_direction(model->options) == pqn_direction.defined(), "learned model",
          takes_pqn_direction(model->options) ? "takes pqn's direction as an input, and none was given"
                                              : "does not take pqn's direction as an input");
  const FNO2dOutput out = model->forward(learned_inputs(gradient, state, pqn_direction));
  const auto previous_scale = state.scale.defined()
                                  ? state.scale
                                  : torch::full({gradient.size(0), 1, 1, 1}, kInitialStepScale, gradient.options());
  const auto d = out.scale.view({-1, 1, 1, 1});
  LearnedStep step;
  step.scale = (previous_scale.detach() * torch::exp(2.0 * torch::tanh(0.5 * d))).clamp(kMinStepScale, kMaxStepScale);
  step.delta = torch::tanh(out.field) * step.scale * free_mask;
  return step;
}

void check_learned_model(const FNO2dOptions& options, const std::string& path) {
  const auto in = options.in_channels();
  const bool per_coordinate = (in == 3 || in == 4) && options.out_channels() == 1;
  const bool combined = (in == 9 || in == 12) && options.out_channels() == 3;
  require((per_coordinate || combined) && options.scale_head(), path,
          "not a learned-optimizer model (needs an FNO with 3 or 4 input channels and 1 output channel, or 9 or 12 "
          "and 3, and a scale head; this one has " +
              std::to_string(options.in_channels()) + " in, " + std::to_string(options.out_channels()) + " out" +
              (options.scale_head() ? "" : ", no scale head") + ")");
}

FNO2dOptions pqn_direction_input_options(FNO2dOptions options) {
  require(!takes_pqn_direction(options), "learned model", "already takes pqn's direction as an input");
  check_learned_model(options, "learned model");
  return options.in_channels(options.in_channels() + (samples_per_environment(options) == 3 ? 1 : 3));
}

FNO2d with_pqn_direction_input(const FNO2d& model) {
  const FNO2dOptions options = pqn_direction_input_options(model->options);
  const int64_t old_inputs = model->options.in_channels();
  const int64_t added = options.in_channels() - old_inputs;
  FNO2d widened(options);
  torch::NoGradGuard no_grad;
  const auto from = model->named_parameters();
  for (auto& p : widened->named_parameters()) {
    const torch::Tensor& source = from[p.key()];
    if (source.sizes() == p.value().sizes()) {
      p.value().copy_(source);
      continue;
    }
    // The lifting layer's weight [lifting, in + 2]: columns of the old inputs, then the new
    // ones (zero), then the two grid channels (fno2d.hpp).
    p.value().zero_();
    p.value().narrow(1, 0, old_inputs).copy_(source.narrow(1, 0, old_inputs));
    p.value().narrow(1, old_inputs + added, 2).copy_(source.narrow(1, old_inputs, 2));
  }
  return widened;
}

FNO2d load_learned_model(const std::string& path) {
  check_learned_model(load_fno_options(path), path);
  return load_fno(path);
}

}  // namespace fnopt
