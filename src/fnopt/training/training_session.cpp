#include <fnopt/training/training_session.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

constexpr const char* kLogHeader =
    "step,seconds,loss,newton_loss,mean_ratio,gradient_norm,learning_rate,renewed,skipped,ratio_without_probe";

// e3d_x1e2 is the score (one grid's mean, or the geometric mean of several); grid_e3d_x1e2 each grid's mean,
// "+"-separated as the resolution column. Logs written before it have the first ten columns only.
const std::string kValidationHeader = std::string("step,seconds,") + kValidationScoreColumns;

// Keeps a CSV log's rows up to `step` (those the checkpoint had seen), so a resumed run's log
// reads as one run; returns the kept rows, split into fields.
std::vector<std::vector<std::string>> trim_log(const std::string& path, const std::string& header, int step) {
  std::ifstream in(path);
  std::ostringstream kept;
  kept << header << '\n';
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    for (std::string_view field : split(line, ',')) fields.emplace_back(field);
    if (fields.size() < 2 || fields[0].empty() || std::stoi(fields[0]) > step) break;
    kept << line << '\n';
    rows.push_back(std::move(fields));
  }
  in.close();
  write_text_atomically(path, kept.str());
  return rows;
}

struct BestValidation {
  double e3d = std::numeric_limits<double>::infinity();
  int step = -1;  // -1: none yet
};

// The best of the validation log's rows of this validation scene, and whether one of them
// scored `step`.
BestValidation best_of(const std::vector<std::vector<std::string>>& rows, const ValidationOptions& v, int step,
                       bool& has_step) {
  BestValidation best;
  has_step = false;
  for (const auto& row : rows) {
    if ((row.size() != 10 && row.size() != 11) ||
        std::vector<std::string>(row.begin() + 2, row.begin() + 7) != RolloutValidation::scene_key(v))
      continue;
    has_step = has_step || std::stoi(row[0]) == step;
    if (std::stod(row[7]) < best.e3d) best = {std::stod(row[7]), std::stoi(row[0])};
  }
  return best;
}

}  // namespace

void TrainingSessionOptions::validate() const {
  require(std::isfinite(minutes) && minutes >= 0.0, "minutes", "must be 0 (no limit) or a positive number of minutes");
  require(checkpoint_every > 0, "checkpoint-every", "must be positive");
  require(validate_every > 0, "validate-every", "must be positive");
  if (validation) with_flag_names(ValidationOptions::flag_names("validate-"), [&] { validation->validate(); });
}

namespace {

// Where a session writes: OUT/checkpoint.pt, model.pt, train_log.csv, validation.csv, model-best.pt.
struct SessionPaths {
  explicit SessionPaths(const std::string& directory)
      : out(directory),
        checkpoint((out / "checkpoint.pt").string()),
        model((out / "model.pt").string()),
        log((out / "train_log.csv").string()),
        validation_log((out / "validation.csv").string()),
        best_model((out / "model-best.pt").string()) {}
  std::filesystem::path out;
  std::string checkpoint, model, log, validation_log, best_model;
};

// What the pool and the loss do, as the banner says it.
void print_objective(const TrainOptions& train) {
  const int subspace = train.pool.subspace;
  if (train.objective == TrainObjective::Probe) {
    const ProbeLossOptions& probe = train.probe;
    std::fprintf(stderr,
                 "fnopt train: objective probe: the model as fnopt-pqn's probe at the first iteration of each time "
                 "step, scored after %d pqn iteration%s on the step's %s; the pool follows Newton's solution\n",
                 probe.iterations, probe.iterations == 1 ? "" : "s",
                 probe.surface == ProbeSurface::Energy ? "energy" : "quadratic model");
    return;
  }
  const std::string kept = " over the last " + std::to_string(subspace) +
                           (train.pool.pqn_direction ? " directions" : " proposals") +
                           ", carried across time steps, and the energy safeguard";
  const std::string rule = subspace == 0 ? "as it is"
                           : train.pool.pqn_direction
                               ? "as fnopt does: pqn's direction -A^-1 g, then the subspace step" + kept
                               : "as fnopt-ss does: subspace step" + kept;
  std::fprintf(stderr, "fnopt train: the pool takes each proposal %s\n", rule.c_str());
  std::fprintf(stderr, "fnopt train: the loss scores each update %s\n",
               train.score_after_subspace_step ? "where the rule ends, past the subspace step" : "at the proposal");
}

void print_banner(const TrainingSessionOptions& options, const Communicator& processes, bool resuming) {
  std::fprintf(stderr, "fnopt train: %s, %d thread%s%s, writing %s\n", options.train.signature().c_str(),
               options.threads, options.threads == 1 ? "" : "s",
               processes.size() > 1 ? (" in each of " + std::to_string(processes.size()) + " processes").c_str() : "",
               options.out.c_str());
  std::fprintf(stderr, "fnopt train: pool ranges (grid units, damping as c dt): %s\n",
               options.train.pool.ranges.text().c_str());
  print_objective(options.train);
  if (!options.train.initial_model.empty() && !resuming)
    std::fprintf(stderr, "fnopt train: starting from the weights of %s\n", options.train.initial_model.c_str());
}

// One session: the trainer, its logs and checkpoints, the validation; rank 0 writes every file.
class Session {
 public:
  Session(const TrainingSessionOptions& options, const Communicator& processes)
      : options_(options),
        processes_(processes),
        settings_(options.validation.value_or(ValidationOptions{})),
        paths_(options.out),
        root_(processes.is_root()) {}

  TrainingSessionResult run();

 private:
  void check_checkpoint() const;
  void open_logs();
  void open_validation();
  void validate(int step);
  void log_step(const TrainStepStats& s, int step);
  void save();
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  const TrainingSessionOptions& options_;
  const Communicator& processes_;
  // The validation scene's settings; a run without validation still reads an earlier run's log.
  const ValidationOptions settings_;
  const SessionPaths paths_;
  const bool root_;
  std::optional<MetaTrainer> trainer_;
  double seconds_before_ = 0.0;
  BestValidation best_;
  bool validated_start_ = false;  // the validation log has a row for the resumed step
  std::unique_ptr<RolloutValidation> validation_;
  std::ofstream log_;
  std::chrono::steady_clock::time_point start_;
  std::optional<ProgressBar> bar_;
  double running_loss_ = NAN, running_ratio_ = NAN, running_baseline_ = NAN;
};

void Session::check_checkpoint() const {
  require(!options_.resume || std::filesystem::exists(paths_.checkpoint), "resume",
          "no checkpoint to resume: " + paths_.checkpoint + " does not exist");
  if (!options_.resume)
    require(!std::filesystem::exists(paths_.checkpoint), "out",
            paths_.checkpoint + " exists: pass --resume to continue it, or choose another --out");
}

// A resumed run's logs keep the rows up to its checkpoint; a fresh run starts them afresh (a
// resumed one keeps its validation log if there is one).
void Session::open_logs() {
  const int done = trainer_->completed_steps();
  if (root_ && options_.resume) {
    const auto rows = trim_log(paths_.log, kLogHeader, done);
    if (!rows.empty()) seconds_before_ = std::stod(rows.back()[1]);
    if (std::filesystem::exists(paths_.validation_log))
      best_ = best_of(trim_log(paths_.validation_log, kValidationHeader, done), settings_, done, validated_start_);
    std::fprintf(stderr, "fnopt train: resumed %s at step %d\n", paths_.checkpoint.c_str(), done);
  } else if (root_) {
    std::ofstream(paths_.log) << kLogHeader << '\n';
  }
  if (root_ && options_.validation && (!options_.resume || !std::filesystem::exists(paths_.validation_log)))
    std::ofstream(paths_.validation_log) << kValidationHeader << '\n';
}

void Session::open_validation() {
  if (!root_ || !options_.validation) return;
  const ValidationOptions& v = settings_;
  std::fprintf(stderr, "fnopt train: validation every %d steps: %s N=%d, %d frames of %s at %s against Newton%s\n",
               options_.validate_every, v.optimizer().c_str(), v.iterations, v.frames,
               RolloutValidation::scene_key(v)[1].c_str(), RolloutValidation::grid_set_text(v, true).c_str(),
               v.resolutions.size() > 1 ? " (score: the geometric mean of the grids' e_3D)" : "");
  validation_ = RolloutValidation::open(v, options_.out, "fnopt train");
  if (best_.step >= 0) std::fprintf(stderr, "fnopt train: best so far: step %d, e_3D %.4g\n", best_.step, best_.e3d);
}

// Validates the current model; keeps it as model-best.pt if it is the closest to Newton so far.
void Session::validate(int step) {
  const ValidationScore score = validation_->score(trainer_->output_model());
  std::ofstream row(paths_.validation_log, std::ios::app);
  row << step << ',' << seconds_before_ + elapsed() << ',';
  RolloutValidation::write_score_columns(row, settings_, score);
  row << '\n';
  if (score.e3d < best_.e3d) {
    best_ = {score.e3d, step};
    save_fno(paths_.best_model, trainer_->output_model());
  }
  if (options_.keep_validated) {
    std::filesystem::create_directories(paths_.out / "validated");
    save_fno((paths_.out / "validated" / ("model-" + std::to_string(step) + ".pt")).string(),
             trainer_->output_model());
  }
}

// The step's log row and the progress line's running figures (weight 0.02 per step; a non-finite
// ratio is skipped).
void Session::log_step(const TrainStepStats& s, int step) {
  auto smooth = [](double& running, double value) {
    if (std::isfinite(value)) running = std::isfinite(running) ? 0.98 * running + 0.02 * value : value;
  };
  running_loss_ = std::isfinite(running_loss_) ? 0.98 * running_loss_ + 0.02 * s.loss : s.loss;
  smooth(running_ratio_, s.mean_ratio);
  smooth(running_baseline_, s.ratio_without_probe);
  log_ << step << ',' << seconds_before_ + elapsed() << ',' << s.loss << ',' << s.newton_loss << ',' << s.mean_ratio
       << ',' << s.gradient_norm << ',' << s.learning_rate << ',' << s.renewed << ',' << s.skipped << ',';
  if (std::isfinite(s.ratio_without_probe)) log_ << s.ratio_without_probe;
  log_ << '\n';
  char status[128];
  int written = std::snprintf(status, sizeof status, "loss %.4f ratio %.4f lr %.1e", running_loss_, running_ratio_,
                              s.learning_rate);
  if (std::isfinite(running_baseline_))
    written += std::snprintf(status + written, sizeof status - written, " (pqn alone %.4f)", running_baseline_);
  if (best_.step >= 0)
    std::snprintf(status + written, sizeof status - written, " best e_3D %.3g @%d", best_.e3d, best_.step);
  bar_->update(step, status);
}

void Session::save() {
  trainer_->save_checkpoint(paths_.checkpoint);
  if (root_) save_fno(paths_.model, trainer_->output_model());
}

TrainingSessionResult Session::run() {
  require_writable_directory(options_.out, "out");
  check_checkpoint();
  processes_.barrier();  // no rank may see a checkpoint that this run writes
  trainer_.emplace(options_.train, options_.resume ? paths_.checkpoint : std::string(), processes_);
  open_logs();
  if (root_) print_banner(options_, processes_, options_.resume);
  open_validation();
  if (root_) log_.open(paths_.log, std::ios::app);
  start_ = std::chrono::steady_clock::now();
  if (root_) bar_.emplace("train", options_.train.steps, trainer_->completed_steps());
  // A resumed run that was not validated at its start (validation newly turned on, say)
  // validates the model it starts from first: model-best.pt is never worse than it.
  if (validation_ && options_.resume && !validated_start_) validate(trainer_->completed_steps());
  TrainingSessionResult result;
  while (trainer_->completed_steps() < options_.train.steps) {
    const TrainStepStats s = trainer_->step();
    const int step = trainer_->completed_steps();
    // Rank 0 keeps the time: every rank stops at the same step.
    const bool out_of_time = processes_.any(root_ && options_.minutes > 0 && elapsed() > 60.0 * options_.minutes);
    if (root_) log_step(s, step);
    // Validation comes before the checkpoint of the same step: a run killed in between
    // repeats both (the steps are reproducible), never loses a validation of a saved step.
    if (validation_ && (step % options_.validate_every == 0 || step == options_.train.steps)) {
      // A validation takes minutes at 100^2: the bar says so meanwhile.
      bar_->update(step, "validating " + std::to_string(validation_->scenes().size()) + " rollouts at " +
                             RolloutValidation::grid_set_text(settings_, true));
      validate(step);
    }
    if (step % options_.checkpoint_every == 0 || step == options_.train.steps || out_of_time) {
      log_.flush();
      save();
    }
    if (out_of_time) {
      result.out_of_time = true;
      break;
    }
  }
  result.model_path = paths_.model;
  result.log_path = paths_.log;
  result.best_model_path = paths_.best_model;
  result.validation_log_path = paths_.validation_log;
  result.validation_motions = RolloutValidation::scene_key(settings_)[1];
  result.steps = trainer_->completed_steps();
  result.seconds = seconds_before_ + elapsed();
  result.best_step = best_.step;
  result.best_e3d = best_.e3d;
  if (root_) bar_->finish();
  return result;
}

}  // namespace

TrainingSessionResult run_training_session(const TrainingSessionOptions& options, const Communicator& processes) {
  return Session(options, processes).run();
}

}  // namespace fnopt
