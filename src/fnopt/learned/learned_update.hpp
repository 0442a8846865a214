#pragma once
// The learned update rule (FNOpt's Algorithm 2, docs/design.md §4), shared by inference and
// meta-training. The FNO has 3 inputs and 1 output: each coordinate x, y, z of an environment is
// one single-channel sample, E environments are 3E samples [3E, 1, R, C].
// Per sample, with sigma_g = ||g||/sqrt(RC) and sigma_d likewise for the previous update,
//   inputs  g^ = 10 tanh(g/(10 sigma_g)), g^_prev = 10 tanh(g_prev/(10 sigma_g)),
//           d^_prev = 10 tanh(d_prev/(10 sigma_d))                 (+ the FNO's grid channels)
//   outputs u (a field) and d (the scale head's scalar)
//   update  delta = tanh(u) s,   s <- clamp(s_prev exp(2 tanh(d/2)), 1e-6, 10)
// (FNOpt writes exp(2 tanh(d/2) - 1): with an untrained head, d ~ 0, that shrinks s by e
// every iteration, and in training the updates vanished before the network learned anything
// (docs/design.md §4). Neutral at d = 0, s only moves as learned.)
// delta is in grid units (cell widths per step^2: a position change of delta cell widths), so
// s means the same at every resolution and material. Handle vertices are masked.
#include <torch/torch.h>

#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

inline constexpr double kInitialStepScale = 0.05;  // s at the first iteration
inline constexpr double kMinStepScale = 1e-6;      // the bounds s is clamped to
inline constexpr double kMaxStepScale = 10.0;

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

// One update from the masked gradient [S, 1, R, C]; `free_mask` [1 or S, 1, R, C] is 0 at
// handles. Differentiable w.r.t. the model's parameters.
LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask);

// Throws Error("<path>: ...") unless the model has the learned optimizer's architecture: 3
// inputs, 1 output and a scale head. A model of an input layout this version no longer trains or
// runs (one that reads pqn's direction, the grid's size, or one sample with x, y, z as channels)
// is named as such.
void check_learned_model(const FNO2dOptions& options, const std::string& path);
// The model in `path`, checked before its weights are read (Error naming the file if it is
// missing or not a learned optimizer).
FNO2d load_learned_model(const std::string& path);

}  // namespace fnopt
