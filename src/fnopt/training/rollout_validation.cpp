#include <fnopt/training/rollout_validation.hpp>

#include <fnopt/simulation/newton_reference.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <optional>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/learned/learned_optimizer.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/scenes/scene_checks.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include <fnopt/version.hpp>

namespace fnopt {

void ValidationOptions::validate() const {
  require(!resolutions.empty(), "validate.resolutions", "must name at least one grid");
  for (int resolution : resolutions) require(resolution >= 3, "validate.resolutions", "must be at least 3");
  require(frames > 0, "validate.frames", "must be positive");
  require(iterations > 0, "validate.iterations", "must be positive");
  require(!motions.empty(), "validate.motions", "must name at least one motion");
  require(!handles.empty(), "validate.handles", "must name at least one handle preset");
  require_subspace_size(subspace, "validate.subspace");
  require(!pqn_direction || subspace > 0, "validate.pqn_direction", "needs the subspace step (subspace > 0)");
  // The scene checks name the scene's field ("motion", "handles"); the errors name this struct's.
  try {
    for (const std::string& motion : motions) scene_checks::motion_name(motion);
  } catch (const Error& e) {
    throw Error("validate.motions", e.problem());
  }
  try {
    for (const std::string& preset : handles) scene_checks::handle_preset_name(preset);
  } catch (const Error& e) {
    throw Error("validate.handles", e.problem());
  }
  // Every motion with every preset must make a scene on every grid (rot_h1 needs two handles, say).
  for (int resolution : resolutions)
    for (const std::string& motion : motions)
      for (const std::string& preset : handles) {
        try {
          RolloutValidation::scene_of(*this, resolution, motion, preset);
        } catch (const Error& e) {
          throw Error("validate.handles", "motion " + motion + " with handles " + preset + ": " + e.problem());
        }
      }
}

namespace {

// The reference file holds this scene's reference if it was solved for this scene, by Newton at
// these settings, by this version of fnopt; anything else (another scene, solver or version, an
// unreadable file) means solving it again.
bool holds_reference(const std::string& path, const Scene& scene, const std::string& newton_settings) {
  if (!std::filesystem::exists(path)) return false;
  try {
    const RolloutProvenance provenance = read_rollout_provenance(path);
    return to_scene_text(read_rollout_scene(path)) == to_scene_text(scene) &&
           provenance.optimizer_settings == newton_settings && provenance.version == FNOPT_VERSION;
  } catch (const std::exception&) {
    return false;
  }
}

// "100/xyz_v4", or "100/xyz_v4/diagonal" off the corner preset.
std::string scene_name(const Scene& scene) {
  const std::string name = std::to_string(scene.rows) + "/" + scene.motion;
  return scene.handles == "corner" ? name : name + "/" + scene.handles;
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

Scene RolloutValidation::scene_of(const ValidationOptions& options, int resolution, const std::string& motion,
                                  const std::string& handles) {
  Scene scene;
  scene.rows = scene.cols = resolution;
  scene.motion = motion;
  scene.handles = handles;
  scene.frames = options.frames;
  scene.validate();
  return scene;
}

std::string RolloutValidation::reference_file(const std::string& directory, const ValidationOptions& options,
                                              int resolution, const std::string& motion, const std::string& handles) {
  // Corner scenes keep the names of the files cached before presets could be chosen.
  const std::string preset = handles == "corner" ? "" : "_" + handles;
  return newton_reference_path(directory, "validation_" + std::to_string(resolution) + "_" + motion + preset,
                               scene_of(options, resolution, motion, handles));
}

std::string RolloutValidation::scene_set_text(const ValidationOptions& options) {
  const bool corner_only = options.handles == std::vector<std::string>{"corner"};
  return joined(options.motions, "+") + (corner_only ? "" : "@" + joined(options.handles, "+"));
}

std::string RolloutValidation::grid_set_text(const ValidationOptions& options, bool squares) {
  std::vector<std::string> grids;
  for (int resolution : options.resolutions)
    grids.push_back(std::to_string(resolution) + (squares ? "x" + std::to_string(resolution) : ""));
  return joined(grids, "+");
}

RolloutValidation::RolloutValidation(const ValidationOptions& options, const std::string& reference_directory,
                                     const StepCallback& on_reference_step)
    : options_(options) {
  options_.validate();
  std::vector<std::string> paths;
  std::vector<bool> cached;
  for (int resolution : options_.resolutions)
    for (const std::string& motion : options_.motions)
      for (const std::string& handles : options_.handles) {
        const Scene scene = scene_of(options_, resolution, motion, handles);
        scenes_.push_back(scene);
        resolved_.push_back(resolve(scene));
        paths.push_back(reference_file(reference_directory, options_, resolution, motion, handles));
        cached.push_back(holds_reference(paths.back(), scene, NewtonOptimizer{}.settings()));
      }
  const int to_solve = static_cast<int>(std::count(cached.begin(), cached.end(), false));
  for (std::size_t i = 0; i < scenes_.size(); ++i) {
    if (!cached[i]) {
      const int done_before = references_solved_ * options_.frames;
      auto progress = [&](int done, int, const StepRecord& record) {
        if (on_reference_step) on_reference_step(done_before + done, to_solve * options_.frames, record);
      };
      NewtonOptimizer newton;
      RolloutOptions rollout_options;
      rollout_options.solve = NewtonOptimizer::reference_solve_options();
      const RolloutResult reference = run_rollout(resolved_[i], newton, rollout_options, progress);
      require(!reference.diverged, "validate",
              "the Newton reference of " + scene_name(scenes_[i]) + " diverged: " + reference.divergence);
      write_rollout_file(paths[i], reference, scenes_[i], newton.settings());
      ++references_solved_;
    }
    references_.push_back(read_trajectory_frames(paths[i]));
  }
}

std::map<std::string, std::string> ValidationOptions::flag_names(const std::string& prefix) {
  return {{"validate.resolutions", prefix + "res"},  {"validate.frames", prefix + "frames"},
          {"validate.iterations", prefix + "iters"}, {"validate.motions", prefix + "motions"},
          {"validate.handles", prefix + "handles"},  {"validate.subspace", prefix + "subspace"}};
}

std::vector<std::string> RolloutValidation::scene_key(const ValidationOptions& options) {
  return {grid_set_text(options), scene_set_text(options), std::to_string(options.frames), options.optimizer(),
          std::to_string(options.iterations)};
}

void RolloutValidation::write_score_columns(std::ostream& row, const ValidationOptions& options,
                                            const ValidationScore& score) {
  for (const std::string& field : scene_key(options)) row << field << ',';
  const auto precision = row.precision();
  row << std::setprecision(17) << score.e3d << std::setprecision(6) << ',' << score.max_strain << ','
      << (score.diverged ? "yes" : "no") << ',';
  for (std::size_t g = 0; g < score.grid_e3d.size(); ++g) row << (g ? "+" : "") << score.grid_e3d[g];
  row.precision(precision);
}

std::unique_ptr<RolloutValidation> RolloutValidation::open(const ValidationOptions& options,
                                                           const std::string& directory, const std::string& command) {
  std::optional<ProgressBar> bar;  // only if a reference is solved
  auto validation =
      std::make_unique<RolloutValidation>(options, directory, [&](int done, int total, const StepRecord&) {
        if (!bar) bar.emplace("validation references", total);
        bar->update(done);
      });
  if (bar) bar->finish();
  std::fprintf(stderr, "%s: validation references: %d solved, %d cached in %s\n", command.c_str(),
               validation->references_solved(),
               static_cast<int>(validation->scenes().size()) - validation->references_solved(), directory.c_str());
  return validation;
}

std::string ValidationOptions::optimizer() const {
  if (subspace == 0) return "fnopt-ls";
  if (subspace == kFnoptSubspace) return pqn_direction ? "fnopt" : "fnopt-ss";
  const std::string rule = "fnopt-ss-k" + std::to_string(subspace);
  return pqn_direction ? rule + "-pqn" : rule;
}

ValidationScore RolloutValidation::score(const FNO2d& model, const StepCallback& on_step) const {
  LearnedParams params;
  params.line_search = options_.subspace == 0;
  params.subspace = options_.subspace;
  params.pqn_direction = options_.pqn_direction;
  RolloutOptions rollout_options;
  rollout_options.solve.max_iterations = options_.iterations;
  TrajectoryComparisonOptions comparison;
  comparison.chamfer_enabled = false;

  const FNO2d weights = snapshot(model);
  ValidationScore s;
  const std::size_t per_grid = scenes_.size() / options_.resolutions.size();
  std::vector<double> e3d_sums(options_.resolutions.size(), 0.0);
  for (std::size_t i = 0; i < scenes_.size(); ++i) {
    // One optimizer per rollout: its step scale carries across steps, not across scenes.
    LearnedOptimizer optimizer(weights, "training snapshot", params);
    const int done_before = static_cast<int>(i) * options_.frames;
    auto progress = [&](int done, int, const StepRecord& record) {
      if (on_step) on_step(done_before + done, static_cast<int>(scenes_.size()) * options_.frames, record);
    };
    const RolloutResult rollout = run_rollout(resolved_[i], optimizer, rollout_options, progress);
    s.max_strain = std::max(s.max_strain, rollout.max_strain());
    if (rollout.diverged) {
      s.diverged = true;
      s.divergence += (s.divergence.empty() ? "" : "; ") + scene_name(scenes_[i]) + ": " + rollout.divergence;
    } else {
      e3d_sums[i / per_grid] += compare_trajectories(references_[i], frames_of(rollout), -1.0, comparison).e3d;
    }
  }
  if (s.diverged) return s;
  for (double sum : e3d_sums) s.grid_e3d.push_back(1e2 * sum / static_cast<double>(per_grid));
  // One grid's score is its mean itself, to the bit, as in logs written before several grids could be validated.
  if (s.grid_e3d.size() == 1) {
    s.e3d = s.grid_e3d[0];
    return s;
  }
  double log_sum = 0.0;
  for (double e3d : s.grid_e3d) log_sum += std::log(e3d);
  s.e3d = std::exp(log_sum / static_cast<double>(s.grid_e3d.size()));
  return s;
}

}  // namespace fnopt
