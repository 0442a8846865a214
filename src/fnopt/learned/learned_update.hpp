#pragma once
// The learned update rule (FNOpt's Algorithm 2, docs/design.md §4), shared by inference and
// meta-training, in one of two layouts chosen by the model's channels:
//   per-coordinate (FNOpt; FNO with 3 inputs, 1 output): each coordinate x, y, z of an
//     environment is one single-channel sample, E environments are 3E samples [3E, 1, R, C];
//   combined (FNO with 9 inputs, 3 outputs): one sample per environment with the coordinates
//     as channels, [E, 3, R, C]: a third of the FNO passes, and the coordinates can couple
//     (the stretch Hessian mixes them along every edge).
// A model with one more input field per coordinate (4 inputs, or 12 combined) also reads pqn's
// direction p = -A^-1 g (baselines/pqn_matrix.hpp): A holds the grid's stiffness, which the
// normalised gradient does not, so the FNO can correct a step that already has the right
// length scale instead of finding it (docs/design.md §4). A model with two more input fields per
// sample (5 or 6 inputs, or 11 or 14 combined) reads the grid's size, log2((R - 1)/31) and
// log2((C - 1)/31) as constant fields (0 at 32 x 32): the normalised inputs look alike on every
// grid while the update they ask for does not (the grid-unit stiffness grows with the cell
// count; docs/design.md §4), so one model can act differently at 32^2 and at 100^2.
// Per sample, with sigma_g = ||g||/sqrt(RC) (over all of the sample's channels) and sigma_d
// likewise for the previous update,
//   inputs  g^ = 10 tanh(g/(10 sigma_g)), g^_prev = 10 tanh(g_prev/(10 sigma_g)),
//           d^_prev = 10 tanh(d_prev/(10 sigma_d)),  [p^ = 10 tanh(p/(10 sigma_p))],
//           [log2((R - 1)/31), log2((C - 1)/31)]               (+ the FNO's grid channels)
//   outputs u (a field) and d (the scale head's scalar)
//   update  delta = tanh(u) s,   s <- clamp(s_prev exp(2 tanh(d/2)), 1e-6, 10)
// (FNOpt writes exp(2 tanh(d/2) - 1): with an untrained head, d ~ 0, that shrinks s by e
// every iteration, and in a 400-step trial the updates vanished before the network learned
// anything (remaining-error ratio stuck at 0.99). Neutral at d = 0, s only moves as learned.)
// delta is in grid units (cell widths per step^2: a position change of delta cell widths), so
// s means the same at every resolution and material. Handle vertices are masked.
#include <torch/torch.h>

#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

inline constexpr double kInitialStepScale = 0.05;  // s at the first iteration
inline constexpr double kMinStepScale = 1e-6;      // the bounds s is clamped to
inline constexpr double kMaxStepScale = 10.0;

// Samples per environment: 3 (per-coordinate layout) or 1 (combined layout).
int samples_per_environment(const FNO2dOptions& options);
// Whether the model reads pqn's direction as an input field (4, 6, 12 or 14 inputs).
bool takes_pqn_direction(const FNO2dOptions& options);
// Whether the model reads the grid's size as two constant input fields (5, 6, 11 or 14 inputs).
bool takes_grid_size(const FNO2dOptions& options);
// Coordinate samples [3, 1, R, C] of one environment in the model's layout, and back.
torch::Tensor to_model_layout(const torch::Tensor& coordinate_samples, int samples_per_environment);
torch::Tensor to_coordinate_layout(const torch::Tensor& model_samples);

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

// The FNO's input channels from a gradient, the state, if defined, pqn's direction in the
// gradient's layout and, with `grid_size`, the grid's size fields (no graph: inputs are data).
torch::Tensor learned_inputs(const torch::Tensor& gradient, const LearnedState& state,
                             const torch::Tensor& pqn_direction = {}, bool grid_size = false);

// One update from the masked gradient [S, 1, R, C]; `free_mask` [1 or S, 1, R, C] is 0 at
// handles; `pqn_direction` (grid units, the gradient's layout) for a model that takes it, and
// only then. Differentiable w.r.t. the model's parameters.
LearnedStep learned_step(FNO2d& model, const torch::Tensor& gradient, const LearnedState& state,
                         const torch::Tensor& free_mask, const torch::Tensor& pqn_direction = {});

// Throws Error("<path>: ...") unless the model has one of the learned optimizer's
// architectures: 3 inputs (4 with pqn's direction, 2 more with the grid's size) and 1 output, or
// 9 (12; 2 more) inputs and 3 outputs; and a scale head.
void check_learned_model(const FNO2dOptions& options, const std::string& path);
// A learned optimizer's shape without pqn's direction as input, with the inputs for it: one more
// field per coordinate (3 -> 4, or 9 -> 12 in the combined layout).
FNO2dOptions pqn_direction_input_options(FNO2dOptions options);
// `model` (a learned optimizer without pqn's direction as input) widened to take it: every
// weight copied, the new input's lifting weights zero, so that the widened model proposes
// exactly what `model` does until training moves them.
FNO2d with_pqn_direction_input(const FNO2d& model);
// The same two for the grid's size fields.
FNO2dOptions grid_size_input_options(FNO2dOptions options);
FNO2d with_grid_size_input(const FNO2d& model);
// The model in `path`, checked before its weights are read (Error naming the file if it is
// missing or not a learned optimizer).
FNO2d load_learned_model(const std::string& path);

}  // namespace fnopt
