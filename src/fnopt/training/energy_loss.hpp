#pragma once
// The meta-training loss (docs/design.md §5): the backward-Euler energy after the learned update,
// with its analytic gradient handed to LibTorch (a custom autograd Function), so the energy is
// written once, in cloth/, not again in torch ops. Per environment e, with L* the Newton
// minimum of its time step,
//   r_e = (L_e(a_e + delta_e h/dt^2) - L*_e) / max(L_e(a_e) - L*_e, 1e-9 (L_e(a_0) - L*_e), rounding),
// the fraction of the remaining error this update leaves (1 = no progress, 0 = exact). r is
// scale-free: every material, stage of the solve and resolution weighs alike. The loss is the
// batch mean of r_e for r_e <= 1 and 1 + log r_e above (an overshoot is penalised, smoothly,
// without letting one exploding step dominate the batch); r below -1 (rounding, or a Newton
// reference that stopped early) counts as -1 with no gradient.
//
// With `after_subspace_step` (pools whose rule takes the subspace step), L_e is scored where the
// rule ends after the update, a_e + S c rather than a_e + delta_e when that is lower
// (subspace_step_loss.hpp): the proposal is judged by what it adds to the directions kept.
#include <torch/torch.h>

#include <vector>

#include <fnopt/training/training_env.hpp>

namespace fnopt {

struct EnergyLossBatch {
  std::vector<TrainingEnv*> envs;
  std::vector<double> current_loss;    // L_e(a_e), the iterate before the update
  std::vector<VecX> current_gradient;  // masked gradient of L_e at a_e (for after_subspace_step)
  std::vector<double> ratio;           // r_e, filled by the forward pass
  bool after_subspace_step = false;
  // Data-parallel training (meta_trainer.hpp): `envs` are this process's share of a batch of
  // `environments_in_all`. The loss returned is this share's part of the batch's loss (the parts
  // sum to it) and its gradient is the part of the batch's gradient.
  int environments_in_all = 0;  // 0: envs.size()
};

class EnergyLoss : public torch::autograd::Function<EnergyLoss> {
 public:
  // delta: grid-unit updates, three coordinate samples per environment [3E, 1, R, C].
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor delta, EnergyLossBatch* batch);
  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs);
};

}  // namespace fnopt
