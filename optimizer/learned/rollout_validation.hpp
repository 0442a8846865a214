#pragma once
// Validation of a model in training on the grid it will be used on: the learned optimizer's
// rollout (fnopt-ls, N iterations per step) of a benchmark scene against the Newton reference
// of the same scene, scored by e_3D (trajectory_error.hpp). Why: training at 32^2 keeps
// lowering the 32^2 error while it can break larger grids (README: the step-5500 model
// diverged at 100^2, the step-8800 model reached 174 % strain there, step 7000 did neither),
// so the training loss alone cannot say which checkpoint to ship.
#include <limits>
#include <string>

#include "fno/fno2d.hpp"
#include "io/rollout_file.hpp"
#include "optimizer/rollout.hpp"
#include "scenes/scene.hpp"

namespace fnopt {

struct ValidationOptions {
  int resolution = 100;          // N x N vertices (default material, corner handles)
  std::string motion = "xy_v2";  // a motion name (boundary/trajectory.hpp)
  int frames = 120;              // time steps of the rollout (2 s at dt = 1/60)
  int iterations = 10;           // the learned optimizer's budget per step

  void validate() const;  // Error("validate.<field>: ...") for a bad value
};

struct ValidationScore {
  double e3d = std::numeric_limits<double>::infinity();  // x 10^2, mean over frames; inf if diverged
  double max_strain = 0.0;
  bool diverged = false;
  std::string divergence;   // why and when, empty if it did not diverge
  double seconds = 0.0;     // wall time of the rollout
};

class RolloutValidation {
 public:
  // Reads the Newton reference from `reference_cache` if that file holds this scene, else
  // solves it (to NewtonOptimizer::reference_solve_options, reporting each step to
  // `on_reference_step`) and writes it there.
  RolloutValidation(const ValidationOptions& options, const std::string& reference_cache,
                    const StepCallback& on_reference_step = {});

  // Scores a snapshot of `model` (its parameters are copied; the model is not touched).
  ValidationScore score(const FNO2d& model) const;

  const Scene& scene() const { return scene_; }
  bool reference_was_cached() const { return reference_was_cached_; }

 private:
  ValidationOptions options_;
  Scene scene_;
  TrajectoryFrames reference_;
  bool reference_was_cached_ = false;
};

}  // namespace fnopt
