#pragma once
// The 2-D Fourier Neural Operator of FNOpt (Li et al., ICLR 2021; configuration of Chen et
// al., "FNOPT", WACV 2026, docs/design.md §4):
//   [x, i/R, j/C] → lifting MLP (in+2 → lifting → width, GELU between)
//   → L Fourier layers h ← GELU(K h + W h + b) (spectral convolution K, 1×1 skip W, b; no
//     GELU after the last) → projection MLP (width → projection → out, GELU between),
// plus an optional scale head: a linear map (width → 1) of the spatial max of the hidden
// features output by one Fourier layer, used by the learned optimizer for its step scale.
#include <torch/torch.h>

#include <fnopt/fno/spectral_conv2d.hpp>

namespace fnopt {

struct FNO2dOptions {
  TORCH_ARG(int64_t, in_channels) = 3;
  TORCH_ARG(int64_t, out_channels) = 1;
  TORCH_ARG(int64_t, width) = 64;
  TORCH_ARG(int64_t, fourier_layers) = 4;
  TORCH_ARG(int64_t, modes_x) = 8;  // kx ∈ [−modes_x/2, modes_x/2) along rows; even
  TORCH_ARG(int64_t, modes_y) = 8;  // ky ∈ [0, modes_y/2] along columns; even
  TORCH_ARG(int64_t, lifting_channels) = 256;
  TORCH_ARG(int64_t, projection_channels) = 64;
  TORCH_ARG(bool, scale_head) = true;
  // 0-based index of the Fourier layer whose output (after its GELU) feeds the scale head:
  // 1 = FNOpt's "after the 2nd Fourier layer".
  TORCH_ARG(int64_t, scale_head_layer) = 1;
  // Zero padding of each side by ceil(fraction · size) after lifting, cropped after the last
  // Fourier layer, for non-periodic fields (a fraction, not a cell count, keeps the operator
  // resolution-independent). Off by default.
  TORCH_ARG(double, padding_fraction) = 0.0;
  // A runtime choice, not part of the architecture (not stored in weight files).
  TORCH_ARG(SpectralBackend, spectral_backend) = SpectralBackend::fftw;
};

// Throws fnopt::Error("FNO2d option <name>: <problem>") for the first invalid option.
void validate(const FNO2dOptions& options);

// Every option that shapes the model (not the spectral backend), in one list: what a weights file
// stores (fno_io.hpp) and what two blended models must share (weight_blend.hpp).
template <typename Options, typename Visit>
void for_each_architecture_option(Options& o, Visit&& visit) {
  visit("in_channels", o.in_channels());
  visit("out_channels", o.out_channels());
  visit("width", o.width());
  visit("fourier_layers", o.fourier_layers());
  visit("modes_x", o.modes_x());
  visit("modes_y", o.modes_y());
  visit("lifting_channels", o.lifting_channels());
  visit("projection_channels", o.projection_channels());
  visit("scale_head", o.scale_head());
  visit("scale_head_layer", o.scale_head_layer());
  visit("padding_fraction", o.padding_fraction());
}

struct FNO2dOutput {
  torch::Tensor field;  // [B, out_channels, R, C]
  torch::Tensor scale;  // [B, 1], undefined without a scale head
};

// Wall time of one forward pass per stage, for the benchmark.
struct FNO2dStageTimes {
  double lifting_ms = 0;     // grid channels, lifting MLP
  double spectral_ms = 0;    // spectral convolutions
  double skip_ms = 0;        // 1×1 skips and their sum with the spectral part
  double projection_ms = 0;  // projection MLP
  double other_ms = 0;       // GELU between layers, padding, scale head
};

class FNO2dImpl : public torch::nn::Module {
 public:
  explicit FNO2dImpl(const FNO2dOptions& options = {});

  // x: [B, in_channels, R, C], any R, C ≥ 1, same dtype as the parameters.
  FNO2dOutput forward(const torch::Tensor& x);
  // forward(), adding each stage's wall time to `times`.
  FNO2dOutput forward_profiled(const torch::Tensor& x, FNO2dStageTimes& times);

  // The options it was built with. Only spectral_backend and padding_fraction may be changed
  // afterwards; the others shape the parameters.
  FNO2dOptions options;

 private:
  FNO2dOutput run(const torch::Tensor& x, FNO2dStageTimes* times);

  torch::nn::Linear lift_in_{nullptr}, lift_out_{nullptr};
  std::vector<SpectralConv2d> spectral_;
  std::vector<torch::nn::Linear> skip_;
  torch::nn::Linear project_in_{nullptr}, project_out_{nullptr};
  torch::nn::Linear scale_head_{nullptr};
};
TORCH_MODULE(FNO2d);

}  // namespace fnopt
