#pragma once
// How compare measures one run (docs/design.md §8): timed at a fixed thread count, against the
// scene's Newton reference (e_CD, e_3D), the per-step error on sampled reference states, and
// against ARCSim where its frames exist.
#include <cstddef>
#include <memory>
#include <optional>

#include <fnopt/studies/compare/step_error.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/studies/compare/compare_study.hpp>

namespace fnopt {

// What every run on one scene shares: the resolved scene, its reference frames, the per-step
// error bench on them (16 Newton solves by default: built once per scene and rank) and the
// ARCSim frames if there are any.
struct CompareScene {
  std::size_t scene = static_cast<std::size_t>(-1);  // index into CompareStudy::scenes
  std::optional<ResolvedScene> resolved;
  TrajectoryFrames reference;
  std::unique_ptr<StepErrorBench> bench;
  std::optional<TrajectoryFrames> arcsim;
};

CompareScene make_compare_scene(const CompareStudy& study, std::size_t scene, ResolvedScene resolved,
                                TrajectoryFrames reference);

// A rollout and the share of a core the process got while it ran (CPU time / wall time).
struct TimedRollout {
  RolloutResult rollout;
  double cpu_share = NAN;
};

TimedRollout timed_rollout(const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options,
                           const StepCallback& on_step);

// Fills the measured columns of `result` from the run's rollout; `choice` makes a fresh
// optimizer for the per-step error (no state from the rollout). With keep_rollouts, also writes
// the rollout to the output directory.
void measure_run(const CompareStudy& study, const CompareScene& scene, const OptimizerChoice& choice,
                 const InnerOptimizer& optimizer, const TimedRollout& timed, RunResult& result);

}  // namespace fnopt
