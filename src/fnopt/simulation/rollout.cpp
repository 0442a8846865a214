#include <fnopt/simulation/rollout.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/simulation/simulator.hpp>

namespace fnopt {

double RolloutResult::mean_step_ms() const {
  double total = 0.0;
  for (const auto& s : steps) total += s.wall_ms;
  return steps.empty() ? 0.0 : total / steps.size();
}

double RolloutResult::max_strain() const {
  double m = 0.0;
  for (const auto& s : steps) m = std::max(m, s.max_strain);
  return m;
}

int RolloutResult::total_iterations() const {
  int n = 0;
  for (const auto& s : steps) n += s.iterations;
  return n;
}

int RolloutResult::converged_steps() const {
  return static_cast<int>(
      std::count_if(steps.begin(), steps.end(), [](const StepRecord& s) { return is_converged(s.status); }));
}

double ms_per_frame(const RolloutResult& rollout) {
  const int n = static_cast<int>(rollout.steps.size());
  const int warmup = std::min(10, n / 5);
  double total = 0.0;
  for (int k = warmup; k < n; ++k) total += rollout.steps[k].wall_ms;
  return n > warmup ? total / (n - warmup) : std::nan("");
}

RolloutResult run_rollout(const ResolvedScene& setup, InnerOptimizer& optimizer, const RolloutOptions& options,
                          const StepCallback& on_step) {
  Simulator simulator(setup, optimizer, options);
  const int frames = setup.scene.frames;
  RolloutResult result;
  result.grid = setup.grid;
  result.rest_positions = setup.start_positions();
  result.handle_vertices = setup.handles.vertices;
  result.dt = setup.scene.dt;
  result.times.push_back(0.0);
  result.positions.push_back(simulator.positions().cast<float>());
  result.handle_targets.push_back(simulator.trajectory_targets(0.0));
  for (int step = 0; step < frames; ++step) {
    const std::vector<Vec3> targets = simulator.trajectory_targets((step + 1) * setup.scene.dt);
    result.steps.push_back(simulator.step(targets));
    if (on_step) on_step(step + 1, frames, result.steps.back());
    if (simulator.diverged()) {
      result.diverged = true;
      result.divergence = simulator.divergence();
      break;
    }
    result.times.push_back(simulator.time());
    result.positions.push_back(simulator.positions().cast<float>());
    result.handle_targets.push_back(targets);
  }
  return result;
}

}  // namespace fnopt
