#pragma once
// Validation of a model in training on the grid it will be used on: the learned optimizer's
// rollouts (fnopt-ss by default, N iterations per step) of benchmark scenes against the Newton references
// of the same scenes, scored by e_3D (trajectory_error.hpp) averaged over the scenes of each grid, then
// geometrically over the grids. Why: training at 32^2 keeps lowering the 32^2 error while it can break larger
// grids (docs/history/training-experiments.md, "Stage 2's end"), and a pool with fine grids gives up 32^2
// (docs/results.md), so the training loss alone cannot say which checkpoint to ship.
#include <limits>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/learned/proposal_rule.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {

struct ValidationOptions {
  // N x N grids (default material). With several, the score is the geometric mean of the grids' means: a
  // checkpoint ranks by relative changes, so a 10 % gain at 32^2 weighs as much as one at 100^2, whose errors
  // are ten times larger (docs/training.md, "Validation at several grids").
  std::vector<int> resolutions = {100};
  // Motion names (boundary/trajectory.hpp). Not xy_v2, rot_h0 or xyz_v3 by default: those are the
  // test scenes of the 64^2 and 100^2 tables in docs/results.md, and a checkpoint chosen on them would
  // make the tables optimistic. Two motions at least, as one alone is a noisy judge
  // (docs/history/training-experiments.md, "Stage 2's end").
  std::vector<std::string> motions = {"xyz_v4", "rot_h1"};
  // Handle presets (boundary/handles.hpp); the scenes are every motion with every preset.
  std::vector<std::string> handles = {"corner"};
  int frames = 120;     // time steps of each rollout (2 s at dt = 1/60)
  int iterations = 10;  // the learned optimizer's budget per step
  // The rule the rollouts take proposals with: fnopt-ss's subspace step over this many
  // proposals (the shipped learned optimizer), or 0 for fnopt-ls, which the validations in
  // docs/history/training-experiments.md before fnopt-ss used.
  int subspace = kFnoptSubspace;
  bool pqn_direction = false;  // fnopt-ss-pqn's rule (LearnedParams::pqn_direction; needs subspace)

  void validate() const;  // Error("validate.<field>: ...") for a bad value
  // The fields validate() names mapped to the flags that set them, each `prefix` + its name ("validate-" in
  // fnopt train, none in fnopt validate), for with_flag_names; pqn_direction is not a flag of its own in train.
  static std::map<std::string, std::string> flag_names(const std::string& prefix);
  // "fnopt-ss" (K = kFnoptSubspace), "fnopt-ss-kK" (another K), either with "-pqn" for
  // pqn_direction, or "fnopt-ls".
  std::string optimizer() const;
};

struct ValidationScore {
  // x 10^2, mean over frames, then over each grid's scenes, then the geometric mean over the grids; inf if any
  // rollout diverged
  double e3d = std::numeric_limits<double>::infinity();
  std::vector<double> grid_e3d;  // x 10^2, each grid's mean over its scenes, in the order of resolutions
  double max_strain = 0.0;       // over all the rollouts
  bool diverged = false;
  std::string divergence;  // "<N>/<motion>[/<handles>]: why and when", empty if none diverged
};

// The columns of a validation score, after those of the run that wrote it (fnopt train's step and seconds, fnopt
// validate's model): the scenes' identity, then the score; one layout for the training's validation.csv and fnopt
// validate's validate.csv.
inline constexpr const char* kValidationScoreColumns =
    "resolution,motions,frames,optimizer,iterations,e3d_x1e2,max_strain,diverged,grid_e3d_x1e2";

class RolloutValidation {
 public:
  // Reads each scene's Newton reference from `reference_directory` (reference_file) if the
  // file there was solved for that scene by Newton at its default settings and by this version
  // of fnopt, else solves it (to NewtonOptimizer::reference_solve_options,
  // reporting each step to `on_reference_step`, counted over all the scenes to solve) and
  // writes it there.
  RolloutValidation(const ValidationOptions& options, const std::string& reference_directory,
                    const StepCallback& on_reference_step = {});

  // The cache file of a scene's reference in `directory` (simulation/newton_reference.hpp).
  static std::string reference_file(const std::string& directory, const ValidationOptions& options, int resolution,
                                    const std::string& motion, const std::string& handles = "corner");
  // The validation scene of a grid, a motion and a handle preset: default material.
  static Scene scene_of(const ValidationOptions& options, int resolution, const std::string& motion,
                        const std::string& handles = "corner");
  // "xyz_v4+rot_h1", with "@corner+diagonal" appended where the presets are not corner alone:
  // the scenes' names in the validation log and the training's messages.
  static std::string scene_set_text(const ValidationOptions& options);
  // "100", or "32+100" for several grids: the validation log's resolution column; with `squares`,
  // "100x100" and "32x32+100x100", for messages.
  static std::string grid_set_text(const ValidationOptions& options, bool squares = false);

  // The first five of kValidationScoreColumns: scores of other scenes are not compared.
  static std::vector<std::string> scene_key(const ValidationOptions& options);
  // The kValidationScoreColumns of `score`, comma-separated, no line end; e_3D at round-trip precision (a resumed
  // training compares later scores with this text).
  static void write_score_columns(std::ostream& row, const ValidationOptions& options, const ValidationScore& score);
  // The validation of `options` with its references in `directory`, those to solve shown by a progress bar on
  // stderr, then "<command>: validation references: N solved, M cached in DIR" (fnopt train and fnopt validate).
  static std::unique_ptr<RolloutValidation> open(const ValidationOptions& options, const std::string& directory,
                                                 const std::string& command);

  // Scores a snapshot of `model` (its parameters are copied; the model is not touched), reporting each step to
  // `on_step`, counted over all the scenes.
  ValidationScore score(const FNO2d& model, const StepCallback& on_step = {}) const;

  const std::vector<Scene>& scenes() const { return scenes_; }
  int references_solved() const { return references_solved_; }  // by the constructor

 private:
  ValidationOptions options_;
  std::vector<Scene> scenes_;            // grid by grid, each grid's motions by motion, then by preset
  std::vector<ResolvedScene> resolved_;  // scenes_, resolved once
  std::vector<TrajectoryFrames> references_;
  int references_solved_ = 0;
};

}  // namespace fnopt
