#include <fnopt/learned/learned_update.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// 10 tanh(x / (10 sigma)) with sigma = ||x||/sqrt(RC) per sample (zero stays zero).
torch::Tensor soft_normalize(const torch::Tensor& x) {
  const auto sigma = x.pow(2).mean({1, 2, 3}, /*keepdim=*/true).sqrt().clamp_min(1e-30);
  return 10.0 * torch::tanh(x / (10.0 * sigma));
}

// The input fields besides the gradient and the state: pqn's direction (one per coordinate) and
// the grid's size (two per sample), recognised by the count of inputs (learned_update.hpp).
struct ExtraInputs {
  bool valid = false, pqn_direction = false, grid_size = false;
};

ExtraInputs extra_inputs(const FNO2dOptions& options) {
  const int64_t in = options.in_channels();
  const bool combined = in >= 9;
  const int64_t extra = in - (combined ? 9 : 3), per_coordinate = combined ? 3 : 1;
  ExtraInputs e;
  for (const bool pqn : {false, true})
    for (const bool grid : {false, true})
      if (extra == (pqn ? per_coordinate : 0) + (grid ? 2 : 0)) e = {true, pqn, grid};
  return e;
}

// `model` with `count` more inputs at `at` (the new options), their lifting weights zero: it proposes what `model`
// does.
FNO2d with_inserted_inputs(const FNO2d& model, const FNO2dOptions& options, int64_t at, int64_t count) {
  const int64_t old_inputs = model->options.in_channels();
  FNO2d widened(options);
  torch::NoGradGuard no_grad;
  const auto from = model->named_parameters();
  for (auto& p : widened->named_parameters()) {
    const torch::Tensor& source = from[p.key()];
    if (source.sizes() == p.value().sizes()) {
      p.value().copy_(source);
      continue;
    }
    // The lifting layer's weight [lifting, in + 2]: the old inputs before `at`, the new ones
    // (zero), the old ones after, then the FNO's two grid channels (fno2d.hpp).
    p.value().zero_();
    p.value().narrow(1, 0, at).copy_(source.narrow(1, 0, at));
    p.value().narrow(1, at + count, old_inputs - at + 2).copy_(source.narrow(1, at, old_inputs - at + 2));
  }
  return widened;
}

}  // namespace

int samples_per_environment(const FNO2dOptions& options) { return options.in_channels() >= 9 ? 1 : 3; }

bool takes_pqn_direction(const FNO2dOptions& options) { return extra_inputs(options).pqn_direction; }

bool takes_grid_size(const FNO2dOptions& options) { return extra_inputs(options).grid_size; }

torch::Tensor to_model_layout(const torch::Tensor& coordinate_samples, int samples_per_environment) {
  if (samples_per_environment == 3) return coordinate_samples;
  return coordinate_samples.view({1, 3, coordinate_samples.size(2), coordinate_samples.size(3)});
}

torch::Tensor to_coordinate_layout(const torch::Tensor& model_samples) {
  return model_samples.reshape({3, 1, model_samples.size(2), model_samples.size(3)});
}

torch::Tensor learned_inputs(const torch::Tensor& gradient, const LearnedState& state,
                             const torch::Tensor& pqn_direction, bool grid_size) {
  const auto sigma_g = gradient.pow(2).mean({1, 2, 3}, true).sqrt().clamp_min(1e-30);
  const auto g_hat = 10.0 * torch::tanh(gradient / (10.0 * sigma_g));
  const auto g_prev =
      state.gradient.defined() ? 10.0 * torch::tanh(state.gradient / (10.0 * sigma_g)) : torch::zeros_like(gradient);
  const auto d_prev = state.delta.defined() ? soft_normalize(state.delta) : torch::zeros_like(gradient);
  std::vector<torch::Tensor> fields = {g_hat, g_prev, d_prev};
  if (pqn_direction.defined()) fields.push_back(soft_normalize(pqn_direction));
  if (grid_size) {
    const int64_t samples = gradient.size(0), rows = gradient.size(2), cols = gradient.size(3);
    auto size_field = [&](int64_t n) {
      return torch::full({samples, 1, rows, cols},
                         std::log2((static_cast<double>(std::max<int64_t>(n, 2)) - 1.0) / 31.0), gradient.options());
    };
    fields.push_back(size_field(rows));
    fields.push_back(size_field(cols));
  }
  return torch::cat(fields, 1).detach();
}

LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask, const torch::Tensor& pqn_direction) {
  require(takes_pqn_direction(model->options) == pqn_direction.defined(), "learned model",
          takes_pqn_direction(model->options) ? "takes pqn's direction as an input, and none was given"
                                              : "does not take pqn's direction as an input");
  const FNO2dOutput out =
      model->forward(learned_inputs(gradient, state, pqn_direction, takes_grid_size(model->options)));
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
  const bool combined = options.in_channels() >= 9;
  const bool outputs = options.out_channels() == (combined ? 3 : 1);
  require(extra_inputs(options).valid && outputs && options.scale_head(), path,
          "not a learned-optimizer model (needs an FNO with 3 to 6 input channels and 1 output channel, or 9, 11, "
          "12 or 14 and 3, and a scale head; this one has " +
              std::to_string(options.in_channels()) + " in, " + std::to_string(options.out_channels()) + " out" +
              (options.scale_head() ? "" : ", no scale head") + ")");
}

FNO2dOptions pqn_direction_input_options(FNO2dOptions options) {
  require(!takes_pqn_direction(options), "learned model", "already takes pqn's direction as an input");
  check_learned_model(options, "learned model");
  return options.in_channels(options.in_channels() + (samples_per_environment(options) == 3 ? 1 : 3));
}

FNO2d with_pqn_direction_input(const FNO2d& model) {
  // pqn's direction comes after the gradient and the state, before the grid's size fields.
  const FNO2dOptions options = pqn_direction_input_options(model->options);
  const int64_t at = samples_per_environment(options) == 3 ? 3 : 9;
  return with_inserted_inputs(model, options, at, options.in_channels() - model->options.in_channels());
}

FNO2dOptions grid_size_input_options(FNO2dOptions options) {
  require(!takes_grid_size(options), "learned model", "already takes the grid's size as an input");
  check_learned_model(options, "learned model");
  return options.in_channels(options.in_channels() + 2);
}

FNO2d with_grid_size_input(const FNO2d& model) {
  const FNO2dOptions options = grid_size_input_options(model->options);
  return with_inserted_inputs(model, options, model->options.in_channels(), 2);
}

FNO2d load_learned_model(const std::string& path) {
  check_learned_model(load_fno_options(path), path);
  return load_fno(path);
}

}  // namespace fnopt
