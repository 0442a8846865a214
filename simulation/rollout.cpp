#include "simulation/rollout.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "boundary/dirichlet.hpp"
#include "cloth/backward_euler.hpp"
#include "cloth/strain.hpp"

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
  return static_cast<int>(std::count_if(steps.begin(), steps.end(), [](const StepRecord& s) { return is_converged(s.status); }));
}

namespace {

// A strain as on the console: "318 %".
std::string percent_text(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f %%", 100.0 * fraction);
  return text;
}

}  // namespace

double ms_per_frame(const RolloutResult& rollout) {
  const int n = static_cast<int>(rollout.steps.size());
  const int warmup = std::min(10, n / 5);
  double total = 0.0;
  for (int k = warmup; k < n; ++k) total += rollout.steps[k].wall_ms;
  return n > warmup ? total / (n - warmup) : std::nan("");
}

RolloutResult run_rollout(const ResolvedScene& setup, InnerOptimizer& optimizer, const RolloutOptions& options,
                          const StepCallback& on_step) {
  const Scene& scene = setup.scene;
  const Grid& grid = setup.grid;
  BackwardEulerObjective objective(grid, scene.material, scene.dt, scene.gravity);
  const DirichletSet dirichlet(grid.vertex_count(), setup.handles.vertices);
  StepProblem problem(objective, dirichlet);

  RolloutResult result;
  result.grid = grid;
  result.handle_vertices = setup.handles.vertices;
  result.dt = scene.dt;
  const int handle_count = static_cast<int>(setup.handles.vertices.size());
  auto targets_at = [&](double t) {
    std::vector<Vec3> targets(handle_count);
    for (int h = 0; h < handle_count; ++h) targets[h] = setup.trajectory->position(h, t);
    return targets;
  };

  VecX x = grid.rest_positions(), v = VecX::Zero(grid.dof_count()), a = VecX::Zero(grid.dof_count());
  result.times.push_back(0.0);
  result.positions.push_back(x.cast<float>());
  result.handle_targets.push_back(targets_at(0.0));

  for (int step = 0; step < scene.frames; ++step) {
    const double t_next = (step + 1) * scene.dt;
    const std::vector<Vec3> targets = targets_at(t_next);
    objective.begin_step(x, v);
    if (!options.warm_start) a.setZero();
    dirichlet.prescribe(a, x, v, targets, scene.dt);

    const auto start = std::chrono::steady_clock::now();
    const InnerSolveResult solve = solve_step(optimizer, problem, a, options.solve);
    const auto stop = std::chrono::steady_clock::now();

    StepRecord record;
    record.wall_ms = std::chrono::duration<double, std::milli>(stop - start).count();
    record.status = solve.status;
    record.iterations = solve.iterations;
    record.initial_loss = solve.initial_value;
    record.loss = solve.value;
    record.initial_gradient_norm = solve.initial_gradient_norm;
    record.gradient_norm = solve.gradient_norm;

    if (solve.status != SolveStatus::NonFinite) {
      v += scene.dt * a;
      x += scene.dt * v;
    }
    const bool finite = solve.status != SolveStatus::NonFinite && x.allFinite();
    record.max_strain = finite ? max_edge_strain(grid, x) : INFINITY;
    record.energy = finite ? objective.kinetic(v) + objective.potential(x) : NAN;
    result.steps.push_back(record);
    if (on_step) on_step(step + 1, scene.frames, record);

    if (!finite || record.max_strain > options.divergence_strain) {
      std::ostringstream why;
      why << "diverged at step " << step + 1 << " (t = " << t_next << " s): "
          << (finite ? "edge strain " + percent_text(record.max_strain) + " above the limit " +
                           percent_text(options.divergence_strain)
                     : std::string("non-finite state"));
      result.diverged = true;
      result.divergence = why.str();
      break;
    }
    result.times.push_back(t_next);
    result.positions.push_back(x.cast<float>());
    result.handle_targets.push_back(targets);
  }
  return result;
}

}  // namespace fnopt
