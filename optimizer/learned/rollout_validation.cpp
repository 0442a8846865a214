#include "optimizer/learned/rollout_validation.hpp"

#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>

#include "baselines/newton.hpp"
#include "metrics/trajectory_error.hpp"
#include "optimizer/learned/learned_optimizer.hpp"
#include "scenes/scene_checks.hpp"
#include "util/error.hpp"

namespace fnopt {

void ValidationOptions::validate() const {
  require(resolution >= 3, "validate.resolution", "must be at least 3");
  require(frames > 0, "validate.frames", "must be positive");
  require(iterations > 0, "validate.iterations", "must be positive");
  try {
    scene_checks::motion_name(motion);
  } catch (const Error& e) {
    throw Error(std::string("validate.") + e.what());
  }
}

namespace {

// The reference file holds this scene if its stored scene text is this scene's; anything else
// (another scene, an unreadable or partial file) means solving it again.
bool holds_scene(const std::string& path, const Scene& scene) {
  if (!std::filesystem::exists(path)) return false;
  try {
    return to_scene_text(read_rollout_scene(path)) == to_scene_text(scene);
  } catch (const std::exception&) {
    return false;
  }
}

FNO2d snapshot(const FNO2d& model) {
  FNO2d copy(model->options);
  torch::NoGradGuard no_grad;
  const auto from = model->parameters();
  auto to = copy->parameters();
  for (std::size_t i = 0; i < from.size(); ++i) to[i].copy_(from[i]);
  return copy;
}

}  // namespace

RolloutValidation::RolloutValidation(const ValidationOptions& options, const std::string& reference_cache,
                                     const StepCallback& on_reference_step)
    : options_(options) {
  options_.validate();
  scene_.rows = scene_.cols = options_.resolution;
  scene_.motion = options_.motion;
  scene_.frames = options_.frames;
  scene_.validate();

  reference_was_cached_ = holds_scene(reference_cache, scene_);
  if (!reference_was_cached_) {
    NewtonOptimizer newton;
    RolloutOptions rollout_options;
    rollout_options.solve = NewtonOptimizer::reference_solve_options();
    const RolloutResult reference = run_rollout(scene_, newton, rollout_options, on_reference_step);
    require(!reference.diverged, "validate", "the Newton reference diverged: " + reference.divergence);
    write_rollout_file(reference_cache, reference, to_scene_text(scene_), newton.settings());
  }
  reference_ = read_trajectory_frames(reference_cache);
}

ValidationScore RolloutValidation::score(const FNO2d& model) const {
  LearnedParams params;
  params.line_search = true;
  LearnedOptimizer optimizer(snapshot(model), "training snapshot", params);
  RolloutOptions rollout_options;
  rollout_options.solve.max_iterations = options_.iterations;

  const auto start = std::chrono::steady_clock::now();
  const RolloutResult rollout = run_rollout(scene_, optimizer, rollout_options);
  ValidationScore s;
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.max_strain = rollout.max_strain();
  s.diverged = rollout.diverged;
  s.divergence = rollout.divergence;
  if (!s.diverged) {
    TrajectoryComparisonOptions comparison;
    comparison.chamfer_enabled = false;
    s.e3d = 1e2 * compare_trajectories(reference_, frames_of(rollout), -1.0, comparison).e3d;
  }
  return s;
}

}  // namespace fnopt
