// fnopt train: meta-train a learned optimizer (docs/design.md §5) with progress, a CSV log,
// checkpoints, --resume and, optionally, a validation rollout on a larger grid that keeps the
// best model (rollout_validation.hpp).
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "app/commands.hpp"
#include <fnopt/util/flag_names.hpp>
#include "app/threads.hpp"
#include <fnopt/parallel/communicator.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/meta_trainer.hpp>
#include <fnopt/training/rollout_validation.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt::app {
namespace {

struct TrainFlags {
  TrainOptions options;
  std::string out;
  int checkpoint_every = 100;
  double minutes = 0.0;
  int threads = 0;  // the default: set_thread_count
  bool resume = false;
  int64_t width = 32, layers = 4, modes = 8, lifting = 64, projection = 32;
  bool combined = false;
  ValidationOptions validation;
  bool validate = false;  // --validate-res given
  int validate_every = 500;
  bool keep_validated = false;  // also keep every validated model
  std::vector<std::string> ranges;  // --range QUANTITY=LOW:HIGH
};

constexpr const char* kLogHeader =
    "step,seconds,loss,newton_loss,mean_ratio,gradient_norm,learning_rate,renewed,skipped,ratio_without_probe";

constexpr const char* kValidationHeader =
    "step,seconds,resolution,motions,frames,optimizer,iterations,e3d_x1e2,max_strain,diverged";

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

// The validation log's identity of a validation scene; rows of another scene are not compared.
std::vector<std::string> validation_key(const ValidationOptions& v) {
  std::string motions;
  for (const std::string& motion : v.motions) motions += (motions.empty() ? "" : "+") + motion;
  return {std::to_string(v.resolution), motions, std::to_string(v.frames), v.optimizer(), std::to_string(v.iterations)};
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
    if (row.size() != 10 || std::vector<std::string>(row.begin() + 2, row.begin() + 7) != validation_key(v)) continue;
    has_step = has_step || std::stoi(row[0]) == step;
    if (std::stod(row[7]) < best.e3d) best = {std::stod(row[7]), std::stoi(row[0])};
  }
  return best;
}

void run_train(TrainFlags& flags) {
  require(std::isfinite(flags.minutes) && flags.minutes >= 0.0, "minutes",
          "must be 0 (no limit) or a positive number of minutes");
  // The model's shape, named by its flags (the model's own checks name its options).
  require(flags.width >= 1, "width", "must be positive");
  require(flags.layers >= 2, "layers",
          "must be at least 2: the step-scale head reads the second Fourier layer's features (docs/design.md §4)");
  require(flags.modes >= 2 && flags.modes % 2 == 0, "modes", "must be a positive even number");
  require(flags.lifting >= 1, "lifting", "must be positive");
  require(flags.projection >= 1, "projection", "must be positive");
  flags.options.model.width(flags.width).fourier_layers(flags.layers).modes_x(flags.modes).modes_y(flags.modes)
      .lifting_channels(flags.lifting).projection_channels(flags.projection)
      .in_channels(flags.combined ? 9 : 3).out_channels(flags.combined ? 3 : 1);
  if (!flags.options.initial_model.empty()) {  // the shape is the file's
    const FNO2dOptions given = load_fno_options(flags.options.initial_model);
    check_learned_model(given, flags.options.initial_model);
    flags.options.model.width(given.width()).fourier_layers(given.fourier_layers()).modes_x(given.modes_x())
        .modes_y(given.modes_y()).lifting_channels(given.lifting_channels())
        .projection_channels(given.projection_channels()).in_channels(given.in_channels())
        .out_channels(given.out_channels());
  }
  require(!flags.validate || flags.options.objective == TrainObjective::Energy, "validate-res",
          "validates fnopt-ss rollouts, not a probe (--objective probe): compare fnopt-pqn with --model instead");
  for (const std::string& text : flags.ranges) {
    std::string quantity;
    double low = 0.0, high = 0.0;
    require(parse_named_interval(text, quantity, low, high), "range",
            "expected QUANTITY=LOW:HIGH, got '" + text + "'");
    with_flag_names({{"train.range", "range"}}, [&] { flags.options.pool.ranges.set(quantity, low, high); });
  }
  with_flag_names({{"train.steps", "steps"},
                   {"train.batch", "batch"},
                   {"train.environments", "envs"},
                   {"train.resolution", "res"},
                   {"train.max_age", "env-lifetime"},
                   {"train.learning_rate", "lr"},
                   {"train.decay_every", "decay-every"},
                   {"train.clip_norm", "clip"},
                   {"train.newton_weight", "newton-weight"},
                   {"train.average_decay", "average-decay"},
                   {"train.score_after_subspace_step", "score"},
                   {"train.subspace", "subspace"},
                   {"train.ranges.undamped_share", "undamped-share"},
                   {"train.range", "range"},
                   {"train.ranges.stretch", "range"},
                   {"train.ranges.shear", "range"},
                   {"train.ranges.bend", "range"},
                   {"train.ranges.gravity", "range"},
                   {"train.ranges.damping", "range"}},
                  [&] { flags.options.validate(); });
  require(flags.validate_every > 0, "validate-every", "must be positive");
  if (flags.validate)
    with_flag_names({{"validate.resolution", "validate-res"},
                     {"validate.frames", "validate-frames"},
                     {"validate.iterations", "validate-iters"},
                     {"validate.motions", "validate-motions"},
                     {"validate.subspace", "validate-subspace"}},
                    [&] { flags.validation.validate(); });
  const int threads = set_thread_count(flags.threads);
  // Under mpirun or srun, every rank trains its share of each batch; rank 0 alone logs,
  // validates and writes (meta_trainer.hpp). Collective steps below: the trainer's, and the
  // stop decision.
  const Communicator& processes = Communicator::world();
  const bool root = processes.is_root();
  require_writable_directory(flags.out, "out");
  const std::filesystem::path out(flags.out);
  const std::string checkpoint = (out / "checkpoint.pt").string();
  const std::string model_path = (out / "model.pt").string();
  const std::string log_path = (out / "train_log.csv").string();
  const std::string validation_log_path = (out / "validation.csv").string();
  const std::string best_model_path = (out / "model-best.pt").string();

  require(!flags.resume || std::filesystem::exists(checkpoint), "resume",
          "no checkpoint to resume: " + checkpoint + " does not exist");
  const bool resuming = flags.resume;
  if (!resuming)
    require(!std::filesystem::exists(checkpoint), "out",
            checkpoint + " exists: pass --resume to continue it, or choose another --out");
  processes.barrier();  // no rank may see a checkpoint that this run writes
  std::optional<MetaTrainer> made;
  with_flag_names({{"train.batch", "batch"}},
                  [&] { made.emplace(flags.options, resuming ? checkpoint : std::string(), processes); });
  MetaTrainer& trainer = *made;
  double seconds_before = 0.0;
  BestValidation best;
  bool validated_start = false;  // the validation log has a row for the resumed step
  if (root && resuming) {
    const auto rows = trim_log(log_path, kLogHeader, trainer.completed_steps());
    if (!rows.empty()) seconds_before = std::stod(rows.back()[1]);
    if (std::filesystem::exists(validation_log_path))
      best = best_of(trim_log(validation_log_path, kValidationHeader, trainer.completed_steps()), flags.validation,
                     trainer.completed_steps(), validated_start);
    std::fprintf(stderr, "fnopt train: resumed %s at step %d\n", checkpoint.c_str(), trainer.completed_steps());
  } else if (root) {
    std::ofstream(log_path) << kLogHeader << '\n';
  }
  // A fresh run starts the validation log afresh; a resumed one keeps it if there is one.
  if (root && flags.validate && (!resuming || !std::filesystem::exists(validation_log_path)))
    std::ofstream(validation_log_path) << kValidationHeader << '\n';
  if (root) {
    std::fprintf(stderr, "fnopt train: %s, %d thread%s%s, writing %s\n", flags.options.signature().c_str(), threads,
                 threads == 1 ? "" : "s",
                 processes.size() > 1 ? (" in each of " + std::to_string(processes.size()) + " processes").c_str() : "",
                 flags.out.c_str());
    std::fprintf(stderr, "fnopt train: pool ranges (grid units, damping as c dt): %s\n",
                 flags.options.pool.ranges.text().c_str());
    const int subspace = flags.options.pool.subspace;
    if (flags.options.objective == TrainObjective::Probe) {
      const ProbeLossOptions& probe = flags.options.probe;
      std::fprintf(stderr,
                   "fnopt train: objective probe: the model as fnopt-pqn's probe at the first iteration of each time "
                   "step, scored after %d pqn iteration%s on the step's %s; the pool follows Newton's solution\n",
                   probe.iterations, probe.iterations == 1 ? "" : "s",
                   probe.surface == ProbeSurface::Energy ? "energy" : "quadratic model");
    } else {
      std::fprintf(stderr, "fnopt train: the pool takes each proposal %s\n",
                   subspace == 0 ? "as it is"
                                 : ("as fnopt-ss does: subspace step over the last " + std::to_string(subspace) +
                                    " proposals, carried across time steps, and the energy safeguard")
                                       .c_str());
      std::fprintf(stderr, "fnopt train: the loss scores each update %s\n",
                   flags.options.score_after_subspace_step ? "where the rule ends, past the subspace step"
                                                           : "at the proposal");
    }
    if (!flags.options.initial_model.empty() && !resuming)
      std::fprintf(stderr, "fnopt train: starting from the weights of %s\n", flags.options.initial_model.c_str());
  }
  std::unique_ptr<RolloutValidation> validation;
  if (root && flags.validate) {
    const ValidationOptions& v = flags.validation;
    std::fprintf(stderr, "fnopt train: validation every %d steps: %s N=%d, %d frames of %s at %dx%d against Newton\n",
                 flags.validate_every, v.optimizer().c_str(), v.iterations, v.frames, validation_key(v)[1].c_str(), v.resolution, v.resolution);
    std::optional<ProgressBar> reference_bar;  // only if a reference is solved
    validation = std::make_unique<RolloutValidation>(v, flags.out, [&](int done, int total, const StepRecord&) {
      if (!reference_bar) reference_bar.emplace("validation references", total);
      reference_bar->update(done);
    });
    if (reference_bar) reference_bar->finish();
    std::fprintf(stderr, "fnopt train: validation references: %d solved, %d cached in %s\n",
                 validation->references_solved(), static_cast<int>(v.motions.size()) - validation->references_solved(),
                 flags.out.c_str());
    if (best.step >= 0) std::fprintf(stderr, "fnopt train: best so far: step %d, e_3D %.4g\n", best.step, best.e3d);
  }

  std::ofstream log;
  if (root) log.open(log_path, std::ios::app);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::optional<ProgressBar> bar;
  if (root) bar.emplace("train", flags.options.steps, trainer.completed_steps());
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
    for (const std::string& field : validation_key(flags.validation)) row << field << ',';
    // e_3D at round-trip precision: a resumed run compares later scores with this text.
    row << std::setprecision(17) << score.e3d << std::setprecision(6) << ',' << score.max_strain << ',' << (score.diverged ? "yes" : "no") << '\n';
    if (score.e3d < best.e3d) {
      best = {score.e3d, step};
      save_fno(best_model_path, trainer.output_model());
    }
    if (flags.keep_validated) {
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
  while (trainer.completed_steps() < flags.options.steps) {
    const TrainStepStats s = trainer.step();
    const int step = trainer.completed_steps();
    // Rank 0 keeps the time: every rank stops at the same step.
    const bool out_of_time = processes.any(root && flags.minutes > 0 && elapsed() > 60.0 * flags.minutes);
    if (root) {
      running_loss = std::isfinite(running_loss) ? 0.98 * running_loss + 0.02 * s.loss : s.loss;
      smooth(running_ratio, s.mean_ratio);
      smooth(running_baseline, s.ratio_without_probe);
      log << step << ',' << seconds_before + elapsed() << ',' << s.loss << ',' << s.newton_loss << ',' << s.mean_ratio
          << ',' << s.gradient_norm << ',' << s.learning_rate << ',' << s.renewed << ',' << s.skipped << ',';
      if (std::isfinite(s.ratio_without_probe)) log << s.ratio_without_probe;
      log << '\n';
      char status[128];
      int written = std::snprintf(status, sizeof status, "loss %.4f ratio %.4f lr %.1e", running_loss,
                                  running_ratio, s.learning_rate);
      if (std::isfinite(running_baseline))
        written += std::snprintf(status + written, sizeof status - written, " (pqn alone %.4f)", running_baseline);
      if (best.step >= 0)
        std::snprintf(status + written, sizeof status - written, " best e_3D %.3g @%d", best.e3d, best.step);
      bar->update(step, status);
    }
    // Validation comes before the checkpoint of the same step: a run killed in between
    // repeats both (the steps are reproducible), never loses a validation of a saved step.
    if (validation && (step % flags.validate_every == 0 || step == flags.options.steps)) validate(step);
    if (step % flags.checkpoint_every == 0 || step == flags.options.steps || out_of_time) {
      log.flush();
      save();
    }
    if (out_of_time) {
      if (!root) return;
      bar->finish();
      std::fprintf(stderr, "fnopt train: stopped after %.1f minutes at step %d; --resume continues\n", flags.minutes,
                   step);
      return;
    }
  }
  if (!root) return;
  bar->finish();
  std::printf("trained %d steps in %s; model %s, log %s\n", trainer.completed_steps(),
              format_duration(seconds_before + elapsed()).c_str(), model_path.c_str(), log_path.c_str());
  if (best.step >= 0)
    std::printf("best validation: step %d, e_3D x 10^2 %.4g at %dx%d (%s); model %s, log %s\n", best.step, best.e3d,
                flags.validation.resolution, flags.validation.resolution, validation_key(flags.validation)[1].c_str(),
                best_model_path.c_str(), validation_log_path.c_str());
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<TrainFlags>();
  TrainOptions& o = flags->options;
  CLI::App* command = app.add_subcommand("train", "meta-train a learned optimizer from the energy alone");
  command->add_option("--out", flags->out, "output folder: model.pt, checkpoint.pt, train_log.csv")->required();
  command->add_option("--steps", o.steps, "training steps")->capture_default_str();
  command->add_option("--objective", o.objective,
                      "what a step scores: energy, the energy after the learned update (the shipped model's "
                      "training); probe, the model as fnopt-pqn's probe: how much of the Newton step's decrease pqn's "
                      "next iterations (--probe-iterations) miss with the pair measured along the proposal (the pool follows Newton's "
                      "solution; --newton-weight does not apply)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, TrainObjective>{{"energy", TrainObjective::Energy}, {"probe", TrainObjective::Probe}}))
      ->option_text("{energy,probe}=energy");
  command->add_option("--probe-iterations", o.probe.iterations,
                      "probe objective: how many pqn iterations after the probe the loss scores (the share of the "
                      "decrease to the step's solution they miss)")
      ->capture_default_str();
  command->add_option("--probe-surface", o.probe.surface,
                      "probe objective: what those iterations run on: model, the step's quadratic model (projected "
                      "Hessian; cheap); energy, the step's energy itself (the loss is then fnopt-pqn's per-step error; "
                      "a gradient per iteration, a Hessian per iteration in the backward pass)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, ProbeSurface>{{"model", ProbeSurface::QuadraticModel}, {"energy", ProbeSurface::Energy}}))
      ->option_text("{model,energy}=model");
  command->add_option("--init", o.initial_model,
                      "start a fresh run from this model's weights (its shape replaces --width, --layers, --modes, "
                      "--lifting, --projection, --combined), e.g. models/fnopt-32.pt");
  command->add_option("--batch", o.batch, "environments per step")->capture_default_str();
  command->add_option("--envs", o.pool.environments, "environments in the pool")->capture_default_str();
  command->add_option("--res", o.pool.resolution, "training resolution")->capture_default_str();
  command->add_option("--env-lifetime", o.pool.max_age,
                      "time steps an environment lives before a new one (material, pose, handles, motion) "
                      "replaces it")
      ->capture_default_str();
  command->add_option("--lr", o.learning_rate, "AdamW learning rate")->capture_default_str();
  command->add_option("--decay-every", o.decay_every, "halve the learning rate every N steps")->capture_default_str();
  command->add_option("--clip", o.clip_norm, "gradient-norm clipping")->capture_default_str();
  command->add_option("--seed", o.seed, "random seed")->capture_default_str();
  command->add_option("--newton-weight", o.newton_weight, "weight of the auxiliary loss toward the Newton step")
      ->capture_default_str();
  command->add_option("--average-decay", o.average_decay,
                      "the model written and validated is the moving average of the trained weights, "
                      "w_avg <- d w_avg + (1 - d) w after every step; 0: the trained weights themselves")
      ->capture_default_str();
  command->add_option("--loss-normalisation", o.loss_normalisation,
                      "per-environment: the mean of each environment's remaining-error ratio; batch: one ratio "
                      "for the batch (FNOpt's mean energy, rescaled)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, LossNormalisation>{
          {"per-environment", LossNormalisation::PerEnvironment}, {"batch", LossNormalisation::Batch}}))
      ->option_text("{per-environment,batch}=per-environment");
  command->add_option("--range", flags->ranges,
                      "sampling range of the pool, QUANTITY=LOW:HIGH, log-uniform, in grid units (repeatable): "
                      "stretch k~_s (default 40:8000), shear k~_sh (0.5:600), bend k~_b (0.005:20), gravity g~ "
                      "(0.03:0.6), damping c dt (0.005:0.3); docs/training.md, \"The training pool in numbers\"");
  command->add_option("--subspace", o.pool.subspace,
                      "how the pool takes each proposal: 0, as it is (the shipped model's training); K, as fnopt-ss "
                      "does: the subspace step over the last K proposals, carried across time steps, and the energy "
                      "safeguard, so the model trains on the states it meets at inference")
      ->capture_default_str();
  command->add_option("--score", o.score_after_subspace_step,
                      "where the loss scores each update: proposal, the energy at a + delta (the shipped model's "
                      "training); subspace-step, where the pool's rule ends after it, past the subspace step (needs "
                      "--subspace K), so a proposal is judged by what it adds to the directions kept")
      ->transform(CLI::CheckedTransformer(std::map<std::string, bool>{{"proposal", false}, {"subspace-step", true}}))
      ->option_text("{proposal,subspace-step}=proposal");
  command->add_option("--undamped-share", o.pool.ranges.undamped_share,
                      "share of the environments without damping")
      ->capture_default_str();
  command->add_option("--width", flags->width, "FNO width")->capture_default_str();
  command->add_option("--layers", flags->layers, "Fourier layers")->capture_default_str();
  command->add_option("--modes", flags->modes, "Fourier modes per axis")->capture_default_str();
  command->add_option("--lifting", flags->lifting, "lifting MLP width")->capture_default_str();
  command->add_option("--projection", flags->projection, "projection MLP width")->capture_default_str();
  command->add_flag("--combined", flags->combined,
                    "one sample per environment with x, y, z as channels (9 in, 3 out) instead of FNOpt's three "
                    "single-channel samples");
  command->add_option("--checkpoint-every", flags->checkpoint_every, "steps between checkpoints")->capture_default_str();
  command->add_option("--minutes", flags->minutes, "stop (with a checkpoint) after this many minutes");
  add_threads_flag(*command, flags->threads);
  command->add_flag("--resume", flags->resume, "continue from OUT/checkpoint.pt");
  CLI::Option* validate_res = command->add_option("--validate-res", flags->validation.resolution,
                      "validate on an N x N grid every --validate-every steps: fnopt-ss rollouts of the benchmark scene "
                      "(default material, corner handles) against their Newton references (solved once, cached in OUT); "
                      "the closest model so far (e_3D) is kept as OUT/model-best.pt, each score in OUT/validation.csv")
      ->each([flags](const std::string&) { flags->validate = true; });
  // The validation's settings: each shows its default and needs --validate-res.
  auto validation_option = [&](const std::string& name, auto& value, const std::string& help) {
    return command->add_option(name, value, help)->capture_default_str()->needs(validate_res);
  };
  validation_option("--validate-every", flags->validate_every, "steps between validations");
  validation_option("--validate-frames", flags->validation.frames, "time steps of the validation rollout");
  command->add_option("--validate-motions", flags->validation.motions,
                      "motions of the validation scenes, comma-separated (default xyz_v3,rot_h0: not xy_v2, the test "
                      "scene of the 64^2 and 100^2 tables in docs/results.md); the score is their mean e_3D")
      ->delimiter(',')
      ->needs(validate_res);
  command->add_flag("--keep-validated", flags->keep_validated,
                    "also keep every validated model as OUT/validated/model-STEP.pt (to compare them later)")
      ->needs(validate_res);
  validation_option("--validate-iters", flags->validation.iterations, "iterations per validation step");
  validation_option("--validate-subspace", flags->validation.subspace,
                    "proposals the validation's subspace step keeps (fnopt-ss); 0 validates with fnopt-ls, as the "
                    "validations before fnopt-ss did");
  command->callback([flags] { run_train(*flags); });
});

}  // namespace
}  // namespace fnopt::app
