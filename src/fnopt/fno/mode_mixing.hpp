#pragma once
// Per-mode complex channel mixing, the learned part of a spectral convolution, and its two
// adjoints. Complex numbers are stored as trailing re/im pairs; the mode axis M is innermost
// so every loop runs over it. All tensors float or double, on the CPU.
#include <torch/torch.h>

namespace fnopt::fno {

// y[b, o, m] = Σ_i x[b, i, m] · w[i, o, m].      x: [B, I, M, 2], w: [I, O, M, 2] → [B, O, M, 2]
torch::Tensor mix_modes(const torch::Tensor& x, const torch::Tensor& w);

// h[b, i, m] = Σ_o g[b, o, m] · conj(w[i, o, m]).  g: [B, O, M, 2], w: [I, O, M, 2] → [B, I, M, 2]
torch::Tensor mix_modes_adjoint_input(const torch::Tensor& g, const torch::Tensor& w);

// gw[i, o, m] = Σ_b g[b, o, m] · conj(x[b, i, m]). g: [B, O, M, 2], x: [B, I, M, 2] → [I, O, M, 2]
torch::Tensor mix_modes_adjoint_weight(const torch::Tensor& g, const torch::Tensor& x);

}  // namespace fnopt::fno
