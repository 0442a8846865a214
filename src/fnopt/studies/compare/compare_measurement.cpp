#include <fnopt/studies/compare/compare_measurement.hpp>

#include <time.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include <fnopt/metrics/cloth_distance.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/simulation/rollout_file.hpp>

namespace fnopt {

namespace fs = std::filesystem;

namespace {

double iterations_per_frame(const RolloutResult& rollout) {
  return rollout.steps.empty() ? std::nan("") : static_cast<double>(rollout.total_iterations()) / rollout.steps.size();
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// A contact scene's closest cloth-cloth approach and intersection counts (RunResult); a scene
// without obstacles or self-contact (the hanging benchmark) measures none, and costs nothing.
void measure_contact(const Scene& scene, const TrajectoryFrames& frames, RunResult& r) {
  const SceneCrossings crossings = count_scene_crossings(scene, frames);
  if (crossings.self < 0) return;
  r.cloth_distance = min_cloth_distance(frames);
  r.self_intersections = static_cast<double>(crossings.self);
  if (crossings.mesh >= 0) r.mesh_intersections = static_cast<double>(crossings.mesh);
}

}  // namespace

CompareScene make_compare_scene(const CompareStudy& study, std::size_t s, ResolvedScene resolved,
                                TrajectoryFrames reference) {
  const Scene& scene = study.scenes[s];
  CompareScene c;
  c.scene = s;
  c.resolved.emplace(std::move(resolved));
  c.reference = std::move(reference);
  c.bench = std::make_unique<StepErrorBench>(scene, c.reference, study.step_samples);
  if (!study.arcsim_dir.empty() && scene.rows == scene.cols && scene.trajectory.empty()) {
    const std::string path =
        (fs::path(study.arcsim_dir) / ("arcsim_N" + resolution_text(scene) + "_" + motion_text(scene) + ".h5"))
            .string();
    if (fs::exists(path)) c.arcsim = read_trajectory_frames(path);
  }
  return c;
}

TimedRollout timed_rollout(const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options,
                           const StepCallback& on_step) {
  const double cpu_start = process_cpu_seconds();
  const auto wall_start = std::chrono::steady_clock::now();
  TimedRollout timed;
  timed.rollout = run_rollout(scene, optimizer, options, on_step);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  timed.cpu_share = wall > 0.0 ? (process_cpu_seconds() - cpu_start) / wall : NAN;
  return timed;
}

void measure_run(const CompareStudy& study, const CompareScene& c, const OptimizerChoice& choice,
                 const InnerOptimizer& optimizer, const TimedRollout& timed, RunResult& r) {
  const Scene& scene = study.scenes[c.scene];
  const RolloutResult& rollout = timed.rollout;
  r.cpu_share = timed.cpu_share;
  if (study.keep_rollouts)
    write_rollout_file((fs::path(study.out) /
                        ("rollout_" + r.spec.method + (r.spec.budget ? "_" + std::to_string(r.spec.budget) : "") + "_" +
                         resolution_text(scene) + "_" + motion_text(scene) + ".h5"))
                           .string(),
                       rollout, scene, optimizer.settings());
  r.frames = static_cast<int>(rollout.steps.size());
  r.ms = ms_per_frame(rollout);
  r.iterations = iterations_per_frame(rollout);
  r.strain = rollout.max_strain();
  if (!scene.obstacles.empty()) r.obstacle_distance = min_obstacle_distance(scene, rollout.positions);
  r.diverged = rollout.diverged;
  if (rollout.diverged) r.note = rollout.divergence;
  const TrajectoryFrames frames = frames_of(rollout);
  measure_contact(scene, frames, r);
  TrajectoryComparisonOptions options;
  options.chamfer = study.chamfer;
  options.chamfer_stride = study.cd_stride;
  // A diverged run has no error to report: over its first frames (the start is exact) it
  // would look better than every run that finished. Its error columns stay empty.
  const TrajectoryComparison comparison = compare_trajectories(c.reference, frames, -1.0, options);
  r.e_cd = rollout.diverged ? NAN : comparison.chamfer;
  r.e_3d = rollout.diverged ? NAN : comparison.e3d;
  if (c.arcsim && !rollout.diverged) r.e_cd_arcsim = compare_trajectories(*c.arcsim, frames, -1.0, options).chamfer;
  const auto fresh = choice.make();  // a fresh optimizer: no state from the rollout
  const StepErrorSummary steps = c.bench->evaluate(*fresh, choice.solve_options());
  r.step_mean = steps.mean;
  r.step_median = steps.median;
}

}  // namespace fnopt
