#pragma once
// 2-D spectral convolution, the global operator of a Fourier layer (Li et al., "Fourier Neural
// Operator for Parametric Partial Differential Equations", ICLR 2021, eq. 5):
//   x̂ = rfft2(x) / (R·C)                    (continuous Fourier coefficients: a model trained
//   ŷ[b,o,kx,ky] = Σ_i x̂[b,i,kx,ky] · W[i,o,kx,ky]   at 32² is the same operator at 100²)
//   y = irfft2(ŷ) without normalisation      (zero outside the kept modes, see kept_modes.hpp)
// Weights are complex, stored as a real tensor [in, out, modes_x, modes_y/2 + 1, 2] (re, im) so
// LibTorch's optimizers see real parameters; the kx axis is centred: index = kx + modes_x/2.
// Inputs are [B, in, R, C] for any R, C ≥ 1, including grids smaller than the modes.
#include <torch/torch.h>

namespace fnopt {

enum class SpectralBackend {
  fftw,       // FFTW plans, custom autograd Function; CPU tensors, float or double
  torch_fft,  // torch::fft with LibTorch's autograd; any device (GPU training)
};

// FFTW version: forward and backward (its adjoint, again FFTs) in a torch::autograd::Function,
// with gradients for x and weight.
torch::Tensor spectral_conv2d(const torch::Tensor& x, const torch::Tensor& weight);

// The same layer written with torch::fft, differentiated by LibTorch: the reference for tests
// and benchmarks, and the backend for devices FFTW does not run on.
torch::Tensor spectral_conv2d_torchfft(const torch::Tensor& x, const torch::Tensor& weight);

torch::Tensor spectral_conv2d(const torch::Tensor& x, const torch::Tensor& weight, SpectralBackend backend);

struct SpectralConv2dOptions {
  SpectralConv2dOptions(int64_t in_channels, int64_t out_channels)
      : in_channels_(in_channels), out_channels_(out_channels) {}
  TORCH_ARG(int64_t, in_channels);
  TORCH_ARG(int64_t, out_channels);
  TORCH_ARG(int64_t, modes_x) = 8;  // kept row frequencies kx ∈ [−modes_x/2, modes_x/2); even
  TORCH_ARG(int64_t, modes_y) = 8;  // kept column frequencies ky ∈ [0, modes_y/2]; even
};

// The layer as a module owning its weight, initialised like neuraloperator's SpectralConv:
// re and im ~ N(0, 1/(in + out)), i.e. E|W|² = 2/(in + out).
class SpectralConv2dImpl : public torch::nn::Module {
 public:
  explicit SpectralConv2dImpl(const SpectralConv2dOptions& options);
  torch::Tensor forward(const torch::Tensor& x, SpectralBackend backend = SpectralBackend::fftw);

  SpectralConv2dOptions options;
  torch::Tensor weight;  // [in, out, modes_x, modes_y/2 + 1, 2]
};
TORCH_MODULE(SpectralConv2d);

}  // namespace fnopt
