#include "optimizer/learned/energy_loss.hpp"

#include <cmath>

#include "optimizer/learned/grid_tensor.hpp"

namespace fnopt {

torch::Tensor EnergyLoss::forward(torch::autograd::AutogradContext* ctx, torch::Tensor delta, EnergyLossBatch* batch) {
  const int count = static_cast<int>(batch->envs.size());
  auto gradient = torch::zeros_like(delta);
  batch->ratio.assign(count, 0.0);
  double total = 0.0;
  VecX trial, g;
  for (int e = 0; e < count; ++e) {
    TrainingEnv& env = *batch->envs[e];
    const Grid& grid = env.grid();
    const double to_acceleration = grid.spacing / (env.dt() * env.dt());
    trial = env.acceleration();
    add_coordinate_samples(delta.narrow(0, 3 * e, 3), grid, to_acceleration, trial);
    const double value = env.objective().value_gradient(trial, g);
    env.dirichlet().zero_fixed(g);
    const double reference = env.reference_loss();
    const double denominator =
        std::max({batch->current_loss[e] - reference, 1e-9 * (env.initial_loss() - reference), 1e-300});
    const double r = (value - reference) / denominator;
    const bool finite = std::isfinite(r) && g.allFinite();
    batch->ratio[e] = finite ? r : INFINITY;
    if (!finite) continue;  // contributes nothing; the environment is renewed when it advances
    total += r <= 1.0 ? r : 1.0 + std::log(r);
    const double d_loss_d_value = (r <= 1.0 ? 1.0 : 1.0 / r) / denominator / count;
    gradient.narrow(0, 3 * e, 3).copy_(to_coordinate_samples(g, grid, d_loss_d_value * to_acceleration));
  }
  ctx->save_for_backward({gradient});
  return torch::tensor(total / count, delta.options());
}

torch::autograd::tensor_list EnergyLoss::backward(torch::autograd::AutogradContext* ctx,
                                                  torch::autograd::tensor_list grad_outputs) {
  const auto gradient = ctx->get_saved_variables()[0];
  return {gradient * grad_outputs[0], torch::Tensor()};
}

}  // namespace fnopt
