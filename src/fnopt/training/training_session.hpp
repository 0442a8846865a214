#pragma once
// A training run as `fnopt train` runs it (docs/training.md): the meta-trainer stepped to its
// step count in an output folder, with a CSV log, checkpoints, --resume that continues exactly
// (the logs trimmed to the checkpoint's step, so a resumed run reads as one run), a time limit
// that stops with a checkpoint, and optionally a validation rollout on a larger grid every so
// many steps that keeps the closest model to Newton as model-best.pt (rollout_validation.hpp).
// Under mpirun every rank trains its share of each batch; rank 0 alone logs, validates and
// writes.
#include <optional>
#include <string>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/training/meta_trainer.hpp>
#include <fnopt/training/rollout_validation.hpp>

namespace fnopt {

struct TrainingSessionOptions {
  TrainOptions train;                           // validated by the caller (its errors name flags)
  std::string out;                              // the output folder: model.pt, checkpoint.pt, train_log.csv
  int checkpoint_every = 100;                   // steps between checkpoints
  double minutes = 0.0;                         // stop with a checkpoint after this long; 0: no limit
  bool resume = false;                          // continue OUT/checkpoint.pt
  std::optional<ValidationOptions> validation;  // validate every validate_every steps
  int validate_every = 500;
  bool keep_validated = false;  // also keep every validated model as OUT/validated/model-STEP.pt
  int threads = 1;              // in effect, for the banner

  // Throws Error("<field>", ...) naming the flag (minutes, checkpoint-every, validate-every).
  void validate() const;
};

struct TrainingSessionResult {
  int steps = 0;                   // completed, the resumed ones included
  double seconds = 0.0;            // training time, the resumed run's included
  bool out_of_time = false;        // stopped by the time limit (--resume continues)
  int best_step = -1;              // the best validated step, -1 if none
  double best_e3d = 0.0;           // its e_3D x 10^2
  std::string validation_motions;  // the validation scenes, "xyz_v4+rot_h1" (RolloutValidation::scene_set_text)
  std::string model_path, log_path, best_model_path, validation_log_path;
};

// Runs the session; collective over `processes`. Throws Error("resume", ...) without a checkpoint
// to resume and Error("out", ...) when OUT holds one and resume is off. The result is rank 0's.
TrainingSessionResult run_training_session(const TrainingSessionOptions& options, const Communicator& processes);

}  // namespace fnopt
