#pragma once
// The two FFTW transforms of the spectral convolution, restricted to the kept modes. The
// adjoint (backward pass) of each is the other one with another scale, so these two are all
// the FFT work forward and backward (see spectral_conv2d.cpp).
#include <torch/torch.h>

#include <fnopt/fno/kept_modes.hpp>

namespace fnopt::fno {

// Kept-mode spectrum of every [R, C] slice of a real field:
//   out[n, k, ky] = scale · Σ_{r,c} field[n, r, c] · exp(−2πi (kx·r/R + ky·c/C)),
// kx = modes.lowest_row_freq + k. field: [N, R, C], float or double, CPU. Result:
// [N, kept_rows, kept_cols, 2] (complex as re/im pairs), same dtype.
torch::Tensor analyze(const torch::Tensor& field, const KeptModes& modes, double scale);

// Real field from a kept-mode spectrum, as torch.fft.irfft2 (unnormalised) computes it for a
// half spectrum that need not be Hermitian: a complex inverse DFT down the columns, then the
// imaginary parts of the self-conjugate columns (ky = 0, C/2) dropped, then c2r along rows:
//   out[n, r, c] = scale · Σ_{k,ky} w_ky · Re(spectrum[n, k, ky] · exp(2πi (kx·r/R + ky·c/C))),
// w_ky = 1 for self-conjugate columns and 2 otherwise. spectrum: [N, kept_rows, kept_cols, 2].
// Result: [N, R, C].
torch::Tensor synthesize(const torch::Tensor& spectrum, const KeptModes& modes, double scale);

}  // namespace fnopt::fno
