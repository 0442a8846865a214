#include <fnopt/learned/learned_update.hpp>

#include <string>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// 10 tanh(x / (10 sigma)) with sigma = ||x||/sqrt(RC) per sample (zero stays zero).
torch::Tensor soft_normalize(const torch::Tensor& x) {
  const auto sigma = x.pow(2).mean({1, 2, 3}, /*keepdim=*/true).sqrt().clamp_min(1e-30);
  return 10.0 * torch::tanh(x / (10.0 * sigma));
}

// The fnopt train option that made a model of in x out channels, for the input layouts this
// version no longer has (docs/design.md §4): one sample with x, y, z as channels (9 inputs,
// 3 outputs; 2 or 3 more with the fields below), pqn's direction as one more input field, the
// grid's size as two more; "" for any other shape.
std::string removed_layout_option(int64_t in, int64_t out) {
  if (out == 3 && (in == 9 || in == 11 || in == 12 || in == 14)) return "--combined";
  if (out != 1) return "";
  if (in == 4) return "--pqn-input";
  if (in == 5) return "--grid-size-input";
  if (in == 6) return "--pqn-input --grid-size-input";
  return "";
}

// The FNO's input channels from a gradient and the state, if defined (no graph: inputs are
// data).
torch::Tensor learned_inputs(const torch::Tensor& gradient, const LearnedState& state) {
  const auto sigma_g = gradient.pow(2).mean({1, 2, 3}, true).sqrt().clamp_min(1e-30);
  const auto g_hat = 10.0 * torch::tanh(gradient / (10.0 * sigma_g));
  const auto g_prev =
      state.gradient.defined() ? 10.0 * torch::tanh(state.gradient / (10.0 * sigma_g)) : torch::zeros_like(gradient);
  const auto d_prev = state.delta.defined() ? soft_normalize(state.delta) : torch::zeros_like(gradient);
  return torch::cat({g_hat, g_prev, d_prev}, 1).detach();
}

}  // namespace

LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask) {
  const FNO2dOutput out = model->forward(learned_inputs(gradient, state));
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
  const int64_t in = options.in_channels(), out = options.out_channels();
  const std::string removed = removed_layout_option(in, out);
  if (!removed.empty())
    throw Error(path, "a model of fnopt train " + removed + ", an option this version no longer has");
  require(in == 3 && out == 1 && options.scale_head(), path,
          "not a learned-optimizer model (needs an FNO with 3 input channels, 1 output channel and a scale head; "
          "this one has " +
              std::to_string(in) + " in, " + std::to_string(out) + " out" +
              (options.scale_head() ? "" : ", no scale head") + ")");
}

FNO2d load_learned_model(const std::string& path) {
  check_learned_model(load_fno_options(path), path);
  return load_fno(path);
}

}  // namespace fnopt
