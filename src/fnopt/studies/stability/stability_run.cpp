#include <fnopt/studies/stability/stability_run.hpp>

#include <algorithm>
#include <map>
#include <sstream>

#include <fnopt/metrics/mesh_intersections.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

StabilityRun run_stability_rollout(const Scene& scene, const StabilityMethod& method, const OptimizerFactory& factory,
                                   const RolloutOptions& base_options, const StepCallback& on_step) {
  StabilityRun run;
  run.frames_requested = scene.frames;
  try {
    const ResolvedScene setup = resolve(scene);  // validates the scene
    {
      const BackwardEulerObjective objective(setup.grid, setup.scene.material, scene.dt, setup.scene.gravity);
      run.initial_energy = objective.potential(setup.start_positions());
    }
    const std::unique_ptr<InnerOptimizer> optimizer = factory(method.method);
    if (!optimizer) throw Error("optimizer", "the factory made no optimizer for '" + method.method + "'");
    RolloutOptions options = base_options;
    options.solve = method.solve;
    run.rollout = run_rollout(setup, *optimizer, options, on_step);
  } catch (const std::exception& e) {
    run.failed = true;
    run.error = e.what();
  }
  return run;
}

const char* to_string(StabilityOutcome outcome) {
  switch (outcome) {
    case StabilityOutcome::Finished:
      return "finished";
    case StabilityOutcome::Diverged:
      return "diverged";
    case StabilityOutcome::Error:
      return "error";
  }
  return "error";
}

int count_unconverged_steps(const RolloutResult& rollout, const InnerSolveOptions& solve, std::string& statuses) {
  std::map<SolveStatus, int> counts;
  for (const StepRecord& s : rollout.steps) {
    const bool normal = is_converged(s.status) || (!solve.to_tolerance() && s.status == SolveStatus::IterationBudget);
    if (!normal) ++counts[s.status];
  }
  statuses.clear();
  int total = 0;
  for (const auto& [status, count] : counts) {
    statuses += (statuses.empty() ? "" : ", ") + std::string(to_string(status)) + " x" + std::to_string(count);
    total += count;
  }
  return total;
}

namespace {

// max and min of E_0 and the finite step energies.
std::pair<double, double> energy_range(const StabilityRun& run) {
  double hi = run.initial_energy, lo = run.initial_energy;
  for (const StepRecord& s : run.rollout.steps)
    if (std::isfinite(s.energy)) hi = std::max(hi, s.energy), lo = std::min(lo, s.energy);
  return {hi, lo};
}

}  // namespace

double energy_growth(const StabilityRun& run, const StabilityRun& reference) {
  if (run.failed || reference.failed || !std::isfinite(run.initial_energy) ||
      !std::isfinite(reference.initial_energy) || reference.rollout.steps.empty())
    return NAN;
  const auto [ref_hi, ref_lo] = energy_range(reference);
  const double hi = energy_range(run).first;
  const double span = ref_hi - ref_lo;
  if (!(span > 0.0)) return NAN;
  const double growth = (hi - ref_lo) / span;
  return std::isfinite(growth) ? growth : NAN;
}

StabilityRow stability_row(const std::string& case_name, const StabilityMethod& method, const StabilityRun& run,
                           const StabilityRun* reference) {
  StabilityRow row;
  row.case_name = case_name;
  row.method = method.method;
  row.reference = method.reference;
  row.solve = method.solve;
  row.frames_requested = run.frames_requested;
  if (run.failed) {
    row.outcome = StabilityOutcome::Error;
    row.reason = run.error;
    return row;
  }
  const RolloutResult& r = run.rollout;
  row.outcome = r.diverged ? StabilityOutcome::Diverged : StabilityOutcome::Finished;
  row.frames_done = static_cast<int>(r.positions.size()) - 1;
  row.diverged_step = r.diverged ? static_cast<int>(r.steps.size()) : 0;
  row.reason = r.divergence;
  double strain = NAN;
  for (const StepRecord& s : r.steps)
    if (std::isfinite(s.max_strain)) strain = std::isnan(strain) ? s.max_strain : std::max(strain, s.max_strain);
  row.max_strain = strain;
  row.ms_per_frame = ms_per_frame(r);
  if (!r.steps.empty()) row.iterations_per_frame = static_cast<double>(r.total_iterations()) / r.steps.size();
  row.unconverged_steps = count_unconverged_steps(r, method.solve, row.unconverged_statuses);
  if (reference && !reference->failed && reference->rollout.positions.size() > 1) {
    row.energy_growth = energy_growth(run, *reference);
    if (r.positions.size() > 1 && r.grid.rows == reference->rollout.grid.rows &&
        r.grid.cols == reference->rollout.grid.cols) {
      TrajectoryComparisonOptions options;
      options.chamfer_enabled = false;
      const TrajectoryComparison c = compare_trajectories(frames_of(reference->rollout), frames_of(r), -1.0, options);
      if (std::isfinite(c.e3d)) row.e3d = c.e3d;
    }
  }
  return row;
}

void count_intersections(const Scene& scene, const StabilityRun& run, StabilityRow& row) {
  if (run.failed) return;
  const SceneCrossings crossings = count_scene_crossings(scene, frames_of(run.rollout));
  row.self_intersections = crossings.self;
  row.mesh_intersections = crossings.mesh;
}

}  // namespace fnopt
