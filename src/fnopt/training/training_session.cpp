#include <fnopt/training/training_session.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
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

TrainingSessionResult run_training_session(const TrainingSessionOptions& options, const Communicator& processes) {
  // The validation scene's settings; a run without validation still reads an earlier run's log.
  const ValidationOptions settings = options.validation.value_or(ValidationOptions{});
  TrainingSessionResult result;
  const bool root = processes.is_root();
  require_writable_directory(options.out, "out");
  const std::filesystem::path out(options.out);
  const std::string checkpoint = (out / "checkpoint.pt").string();
  const std::string model_path = (out / "model.pt").string();
  const std::string log_path = (out / "train_log.csv").string();
  const std::string validation_log_path = (out / "validation.csv").string();
  const std::string best_model_path = (out / "model-best.pt").string();
  result.model_path = model_path;
  result.log_path = log_path;
  result.best_model_path = best_model_path;
  result.validation_log_path = validation_log_path;
  result.validation_motions = RolloutValidation::scene_key(settings)[1];

  require(!options.resume || std::filesystem::exists(checkpoint), "resume",
          "no checkpoint to resume: " + checkpoint + " does not exist");
  const bool resuming = options.resume;
  if (!resuming)
    require(!std::filesystem::exists(checkpoint), "out",
            checkpoint + " exists: pass --resume to continue it, or choose another --out");
  processes.barrier();  // no rank may see a checkpoint that this run writes
  std::optional<MetaTrainer> made;
  made.emplace(options.train, resuming ? checkpoint : std::string(), processes);
  MetaTrainer& trainer = *made;
  double seconds_before = 0.0;
  BestValidation best;
  bool validated_start = false;  // the validation log has a row for the resumed step
  if (root && resuming) {
    const auto rows = trim_log(log_path, kLogHeader, trainer.completed_steps());
    if (!rows.empty()) seconds_before = std::stod(rows.back()[1]);
    if (std::filesystem::exists(validation_log_path))
      best = best_of(trim_log(validation_log_path, kValidationHeader, trainer.completed_steps()), settings,
                     trainer.completed_steps(), validated_start);
    std::fprintf(stderr, "fnopt train: resumed %s at step %d\n", checkpoint.c_str(), trainer.completed_steps());
  } else if (root) {
    std::ofstream(log_path) << kLogHeader << '\n';
  }
  // A fresh run starts the validation log afresh; a resumed one keeps it if there is one.
  if (root && options.validation && (!resuming || !std::filesystem::exists(validation_log_path)))
    std::ofstream(validation_log_path) << kValidationHeader << '\n';
  if (root) {
    std::fprintf(stderr, "fnopt train: %s, %d thread%s%s, writing %s\n", options.train.signature().c_str(),
                 options.threads, options.threads == 1 ? "" : "s",
                 processes.size() > 1 ? (" in each of " + std::to_string(processes.size()) + " processes").c_str() : "",
                 options.out.c_str());
    std::fprintf(stderr, "fnopt train: pool ranges (grid units, damping as c dt): %s\n",
                 options.train.pool.ranges.text().c_str());
    const int subspace = options.train.pool.subspace;
    if (options.train.objective == TrainObjective::Probe) {
      const ProbeLossOptions& probe = options.train.probe;
      std::fprintf(stderr,
                   "fnopt train: objective probe: the model as fnopt-pqn's probe at the first iteration of each time "
                   "step, scored after %d pqn iteration%s on the step's %s; the pool follows Newton's solution\n",
                   probe.iterations, probe.iterations == 1 ? "" : "s",
                   probe.surface == ProbeSurface::Energy ? "energy" : "quadratic model");
    } else {
      const std::string kept = " over the last " + std::to_string(subspace) +
                               (options.train.pool.pqn_direction ? " directions" : " proposals") +
                               ", carried across time steps, and the energy safeguard";
      const std::string rule = subspace == 0 ? "as it is"
                               : options.train.pool.pqn_direction
                                   ? "as fnopt does: pqn's direction -A^-1 g, then the subspace step" + kept
                                   : "as fnopt-ss does: subspace step" + kept;
      std::fprintf(stderr, "fnopt train: the pool takes each proposal %s\n", rule.c_str());
      std::fprintf(
          stderr, "fnopt train: the loss scores each update %s\n",
          options.train.score_after_subspace_step ? "where the rule ends, past the subspace step" : "at the proposal");
    }
    if (!options.train.initial_model.empty() && !resuming)
      std::fprintf(stderr, "fnopt train: starting from the weights of %s\n", options.train.initial_model.c_str());
  }
  std::unique_ptr<RolloutValidation> validation;
  if (root && options.validation) {
    const ValidationOptions& v = settings;
    std::fprintf(stderr, "fnopt train: validation every %d steps: %s N=%d, %d frames of %s at %s against Newton%s\n",
                 options.validate_every, v.optimizer().c_str(), v.iterations, v.frames,
                 RolloutValidation::scene_key(v)[1].c_str(), RolloutValidation::grid_set_text(v, true).c_str(),
                 v.resolutions.size() > 1 ? " (score: the geometric mean of the grids' e_3D)" : "");
    validation = RolloutValidation::open(v, options.out, "fnopt train");
    if (best.step >= 0) std::fprintf(stderr, "fnopt train: best so far: step %d, e_3D %.4g\n", best.step, best.e3d);
  }

  std::ofstream log;
  if (root) log.open(log_path, std::ios::app);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::optional<ProgressBar> bar;
  if (root) bar.emplace("train", options.train.steps, trainer.completed_steps());
  double running_loss = NAN, running_ratio = NAN, running_baseline = NAN;
  // The progress line's running ratios (weight 0.02 per step); a non-finite value is skipped.
  auto smooth = [](double& running, double value) {
    if (std::isfinite(value)) running = std::isfinite(running) ? 0.98 * running + 0.02 * value : value;
  };
  // Validates the current model; keeps it as model-best.pt if it is the closest to Newton so far.
  auto validate = [&](int step) {
    const ValidationScore score = validation->score(trainer.output_model());
    std::ofstream row(validation_log_path, std::ios::app);
    row << step << ',' << seconds_before + elapsed() << ',';
    RolloutValidation::write_score_columns(row, settings, score);
    row << '\n';
    if (score.e3d < best.e3d) {
      best = {score.e3d, step};
      save_fno(best_model_path, trainer.output_model());
    }
    if (options.keep_validated) {
      std::filesystem::create_directories(out / "validated");
      save_fno((out / "validated" / ("model-" + std::to_string(step) + ".pt")).string(), trainer.output_model());
    }
  };
  auto save = [&] {
    trainer.save_checkpoint(checkpoint);
    if (root) save_fno(model_path, trainer.output_model());
  };
  // A resumed run that was not validated at its start (validation newly turned on, say)
  // validates the model it starts from first: model-best.pt is never worse than it.
  if (validation && resuming && !validated_start) validate(trainer.completed_steps());
  while (trainer.completed_steps() < options.train.steps) {
    const TrainStepStats s = trainer.step();
    const int step = trainer.completed_steps();
    // Rank 0 keeps the time: every rank stops at the same step.
    const bool out_of_time = processes.any(root && options.minutes > 0 && elapsed() > 60.0 * options.minutes);
    if (root) {
      running_loss = std::isfinite(running_loss) ? 0.98 * running_loss + 0.02 * s.loss : s.loss;
      smooth(running_ratio, s.mean_ratio);
      smooth(running_baseline, s.ratio_without_probe);
      log << step << ',' << seconds_before + elapsed() << ',' << s.loss << ',' << s.newton_loss << ',' << s.mean_ratio
          << ',' << s.gradient_norm << ',' << s.learning_rate << ',' << s.renewed << ',' << s.skipped << ',';
      if (std::isfinite(s.ratio_without_probe)) log << s.ratio_without_probe;
      log << '\n';
      char status[128];
      int written = std::snprintf(status, sizeof status, "loss %.4f ratio %.4f lr %.1e", running_loss, running_ratio,
                                  s.learning_rate);
      if (std::isfinite(running_baseline))
        written += std::snprintf(status + written, sizeof status - written, " (pqn alone %.4f)", running_baseline);
      if (best.step >= 0)
        std::snprintf(status + written, sizeof status - written, " best e_3D %.3g @%d", best.e3d, best.step);
      bar->update(step, status);
    }
    // Validation comes before the checkpoint of the same step: a run killed in between
    // repeats both (the steps are reproducible), never loses a validation of a saved step.
    if (validation && (step % options.validate_every == 0 || step == options.train.steps)) {
      // A validation takes minutes at 100^2: the bar says so meanwhile.
      bar->update(step, "validating " + std::to_string(validation->scenes().size()) + " rollouts at " +
                            RolloutValidation::grid_set_text(settings, true));
      validate(step);
    }
    if (step % options.checkpoint_every == 0 || step == options.train.steps || out_of_time) {
      log.flush();
      save();
    }
    if (out_of_time) {
      result.out_of_time = true;
      break;
    }
  }
  result.steps = trainer.completed_steps();
  result.seconds = seconds_before + elapsed();
  result.best_step = best.step;
  result.best_e3d = best.e3d;
  if (root) bar->finish();
  return result;
}

}  // namespace fnopt
