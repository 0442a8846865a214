#include <fnopt/training/energy_loss.hpp>

#include <cmath>
#include <utility>
#include <vector>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/subspace_step_loss.hpp>

namespace fnopt {

namespace {

// The smooth overshoot penalty of a ratio r: r up to 1, then 1 + log r. Returns the loss and
// d loss / d r; below -1 (rounding, or a Newton reference that stopped early) it is -1 with
// no gradient.
std::pair<double, double> penalised(double r) {
  if (r < -1.0) return {-1.0, 0.0};
  return r <= 1.0 ? std::make_pair(r, 1.0) : std::make_pair(1.0 + std::log(r), 1.0 / r);
}

}  // namespace

torch::Tensor EnergyLoss::forward(torch::autograd::AutogradContext* ctx, torch::Tensor delta, EnergyLossBatch* batch) {
  const int count = static_cast<int>(batch->envs.size());
  auto gradient = torch::zeros_like(delta);
  batch->ratio.assign(count, 0.0);
  std::vector<double> denominator(count, 0.0);
  std::vector<VecX> energy_gradient(count);  // dL_e/d delta_e in grid units; empty if not finite
  VecX trial;
  for (int e = 0; e < count; ++e) {
    TrainingEnv& env = *batch->envs[e];
    const Grid& grid = env.grid();
    const double to_acceleration = acceleration_per_grid_unit(grid, env.dt());
    trial = env.acceleration();
    add_coordinate_samples(delta.narrow(0, 3 * e, 3), grid, to_acceleration, trial);
    VecX& g = energy_gradient[e];
    StepProblem problem(env.objective(), env.dirichlet());
    double value = problem.value_gradient(trial, g);
    if (batch->after_subspace_step) {
      SubspaceStepOutcome end =
          energy_after_subspace_step(problem, env.rule().pairs(), env.rule().params().min_rescale, env.acceleration(),
                                     batch->current_gradient[e], trial - env.acceleration(), value, g);
      value = end.value;
      g.swap(end.gradient);
    }
    g *= to_acceleration;
    const double reference = env.reference_loss();
    // The floor on the denominator is L's rounding error: an environment at rest has
    // L(a_0) = L*, and there a difference of rounding noise is no progress to score.
    const double rounding = 1e-13 * (std::abs(reference) + std::abs(env.initial_loss()) + 1e-30);
    denominator[e] = std::max({batch->current_loss[e] - reference, 1e-9 * (env.initial_loss() - reference), rounding});
    const double r = (value - reference) / denominator[e];
    const bool finite = std::isfinite(r) && g.allFinite();
    batch->ratio[e] = finite ? r : INFINITY;
    if (!finite) g.resize(0);  // contributes nothing; the environment is renewed when it advances
  }

  auto add_gradient = [&](int e, double d_loss_d_value) {
    const Grid& grid = batch->envs[e]->grid();
    gradient.narrow(0, 3 * e, 3).copy_(to_coordinate_samples(energy_gradient[e], grid, d_loss_d_value));
  };
  double loss = 0.0;
  const int in_all = batch->environments_in_all > 0 ? batch->environments_in_all : count;
  for (int e = 0; e < count; ++e) {
    if (energy_gradient[e].size() == 0) continue;
    const auto [value, slope] = penalised(batch->ratio[e]);
    loss += value / in_all;
    if (slope != 0.0) add_gradient(e, slope / denominator[e] / in_all);
  }
  ctx->save_for_backward({gradient});
  return torch::tensor(loss, delta.options());
}

torch::autograd::tensor_list EnergyLoss::backward(torch::autograd::AutogradContext* ctx,
                                                  torch::autograd::tensor_list grad_outputs) {
  const auto gradient = ctx->get_saved_variables()[0];
  return {gradient * grad_outputs[0], torch::Tensor()};
}

}  // namespace fnopt
