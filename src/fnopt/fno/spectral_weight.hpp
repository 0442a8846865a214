#pragma once
// Shape checks and kept-mode slicing shared by the FFTW and torch::fft spectral convolutions.
#include <torch/torch.h>

#include <fnopt/fno/kept_modes.hpp>

namespace fnopt::fno {

// Kept modes of a weight [in, out, modes_x, modes_y/2 + 1, 2] on the grid of x [B, in, R, C].
// Throws fnopt::Error when the shapes do not fit together.
KeptModes kept_modes_for(const torch::Tensor& x, const torch::Tensor& weight);

// The weight's block of kept modes, [in, out, kept_rows, kept_cols, 2]: the weight itself when
// the grid keeps every mode, a slice when the grid is smaller than the modes.
torch::Tensor kept_weight(const torch::Tensor& weight, const KeptModes& modes);

}  // namespace fnopt::fno
