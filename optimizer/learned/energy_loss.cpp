#include "optimizer/learned/energy_loss.hpp"

#include <cmath>

#include "cloth/grid_units.hpp"
#include "optimizer/learned/grid_tensor.hpp"
#include "optimizer/learned/learned_update.hpp"

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
    const double to_acceleration = acceleration_per_grid_unit(grid, env.dt());
    trial = env.acceleration();
    const int k = batch->samples_per_environment;
    add_coordinate_samples(to_coordinate_layout(delta.narrow(0, k * e, k)), grid, to_acceleration, trial);
    const double value = env.objective().value_gradient(trial, g);
    env.dirichlet().zero_fixed(g);
    const double reference = env.reference_loss();
    // The floor on the denominator is L's rounding error: an environment at rest has
    // L(a_0) = L*, and there a difference of rounding noise is no progress to score.
    const double rounding = 1e-13 * (std::abs(reference) + std::abs(env.initial_loss()) + 1e-30);
    const double denominator =
        std::max({batch->current_loss[e] - reference, 1e-9 * (env.initial_loss() - reference), rounding});
    const double r = (value - reference) / denominator;
    const bool finite = std::isfinite(r) && g.allFinite();
    batch->ratio[e] = finite ? r : INFINITY;
    if (!finite) continue;  // contributes nothing; the environment is renewed when it advances
    // Below L* by more than the whole remaining error is rounding or a Newton reference that
    // stopped early: scored -1, with no gradient.
    if (r < -1.0) {
      total -= 1.0;
      continue;
    }
    total += r <= 1.0 ? r : 1.0 + std::log(r);
    const double d_loss_d_value = (r <= 1.0 ? 1.0 : 1.0 / r) / denominator / count;
    gradient.narrow(0, k * e, k).copy_(to_model_layout(to_coordinate_samples(g, grid, d_loss_d_value * to_acceleration), k));
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
