#pragma once
// The learned update rule (FNOpt's Algorithm 2, DESIGN.md §4), shared by inference and
// meta-training. Each coordinate x, y, z of an environment is one single-channel sample, so a
// batch of E environments is 3E samples [3E, 1, R, C]. Per sample, with sigma_g = ||g||/sqrt(RC)
// and sigma_d likewise for the previous update,
//   inputs  g^ = 10 tanh(g/(10 sigma_g)), g^_prev = 10 tanh(g_prev/(10 sigma_g)),
//           d^_prev = 10 tanh(d_prev/(10 sigma_d))            (+ the FNO's grid channels)
//   outputs u (a field) and d (the scale head's scalar)
//   update  delta = tanh(u) s,   s <- clamp(s_prev exp(2 tanh(d/2)), 1e-6, 10)
// (DESIGN.md writes exp(2 tanh(d/2) - 1): with an untrained head, d ~ 0, that shrinks s by e
// every iteration, and in a 400-step trial the updates vanished before the network learned
// anything (remaining-error ratio stuck at 0.99). Neutral at d = 0, s only moves as learned.)
// delta is in grid units (cell widths per step^2: a position change of delta cell widths), so
// s means the same at every resolution and material. Handle vertices are masked.
#include <torch/torch.h>

#include "fno/fno2d.hpp"

namespace fnopt {

inline constexpr double kInitialStepScale = 0.05;  // s at the first iteration

// Per-sample recurrent state; undefined tensors mean "first iteration".
struct LearnedState {
  torch::Tensor gradient;  // previous masked gradient      [S, 1, R, C]
  torch::Tensor delta;     // previous update (grid units)  [S, 1, R, C]
  torch::Tensor scale;     // step scale s                  [S, 1, 1, 1]
};

struct LearnedStep {
  torch::Tensor delta;  // [S, 1, R, C], grid units, zero at handles
  torch::Tensor scale;  // [S, 1, 1, 1]
};

// The FNO's 3 input channels from a gradient and the state (no graph: inputs are data).
torch::Tensor learned_inputs(const torch::Tensor& gradient, const LearnedState& state);

// One update from the masked gradient [S, 1, R, C]; `free_mask` [1 or S, 1, R, C] is 0 at
// handles. Differentiable w.r.t. the model's parameters.
LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask);

// Throws Error("<path>: ...") unless the model has the learned optimizer's architecture:
// 3 input channels, 1 output channel, a scale head.
void check_learned_model(const FNO2dOptions& options, const std::string& path);

}  // namespace fnopt
