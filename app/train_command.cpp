// fnopt train: its flags, turned into a training session (training/training_session.hpp: the
// meta-trainer with a CSV log, checkpoints, --resume, a time limit and, optionally, a validation
// rollout on a larger grid that keeps the best model).
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/parallel/communicator.hpp>
#include <fnopt/training/training_session.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include "app/commands.hpp"
#include "app/threads.hpp"
#include "app/validation_flags.hpp"

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
  ValidationOptions validation;
  bool validate = false;  // --validate-res given
  int validate_every = 500;
  bool keep_validated = false;      // also keep every validated model
  std::vector<std::string> ranges;  // --range QUANTITY=LOW:HIGH
};

// The model's shape from its flags, named by them (the model's own checks name its options), or
// from --init's file.
void set_model_shape(TrainFlags& flags) {
  require(flags.width >= 1, "width", "must be positive");
  require(flags.layers >= 2, "layers",
          "must be at least 2: the step-scale head reads the second Fourier layer's features (docs/design.md §4)");
  require(flags.modes >= 2 && flags.modes % 2 == 0, "modes", "must be a positive even number");
  require(flags.lifting >= 1, "lifting", "must be positive");
  require(flags.projection >= 1, "projection", "must be positive");
  flags.options.model.width(flags.width)
      .fourier_layers(flags.layers)
      .modes_x(flags.modes)
      .modes_y(flags.modes)
      .lifting_channels(flags.lifting)
      .projection_channels(flags.projection);
  if (flags.options.initial_model.empty()) return;
  const FNO2dOptions given = load_fno_options(flags.options.initial_model);
  check_learned_model(given, flags.options.initial_model);
  flags.options.model.width(given.width())
      .fourier_layers(given.fourier_layers())
      .modes_x(given.modes_x())
      .modes_y(given.modes_y())
      .lifting_channels(given.lifting_channels())
      .projection_channels(given.projection_channels());
}

// The training options' fields and the flags that set them.
const std::map<std::string, std::string>& train_flag_names() {
  static const std::map<std::string, std::string> names = {{"train.steps", "steps"},
                                                           {"train.batch", "batch"},
                                                           {"train.environments", "envs"},
                                                           {"train.resolutions", "res"},
                                                           {"train.max_age", "env-lifetime"},
                                                           {"train.learning_rate", "lr"},
                                                           {"train.decay_every", "decay-every"},
                                                           {"train.clip_norm", "clip"},
                                                           {"train.newton_weight", "newton-weight"},
                                                           {"train.average_decay", "average-decay"},
                                                           {"train.score_after_subspace_step", "score"},
                                                           {"train.subspace", "subspace"},
                                                           {"train.pqn_direction", "pqn-direction"},
                                                           {"train.reference_pqn_iterations", "reference-pqn-iters"},
                                                           {"train.ranges.undamped_share", "undamped-share"},
                                                           {"train.range", "range"},
                                                           {"train.ranges.stretch", "range"},
                                                           {"train.ranges.shear", "range"},
                                                           {"train.ranges.bend", "range"},
                                                           {"train.ranges.gravity", "range"},
                                                           {"train.ranges.damping", "range"}};
  return names;
}

// The session the flags describe, validated.
TrainingSessionOptions session_of(TrainFlags& flags) {
  // fnopt's rule in the pool and in the validation alike: a model trained for it is judged by it.
  flags.validation.pqn_direction = flags.options.pool.pqn_direction;
  set_model_shape(flags);
  require(!flags.validate || flags.options.objective == TrainObjective::Energy, "validate-res",
          "validates fnopt-ss rollouts, not a probe (--objective probe): compare fnopt-pqn with --model instead");
  for (const std::string& text : flags.ranges) {
    std::string quantity;
    double low = 0.0, high = 0.0;
    require(parse_named_interval(text, quantity, low, high), "range", "expected QUANTITY=LOW:HIGH, got '" + text + "'");
    with_flag_names({{"train.range", "range"}}, [&] { flags.options.pool.ranges.set(quantity, low, high); });
  }
  with_flag_names(train_flag_names(), [&] { flags.options.validate(); });
  TrainingSessionOptions session;
  session.train = flags.options;
  session.out = flags.out;
  session.checkpoint_every = flags.checkpoint_every;
  session.minutes = flags.minutes;
  session.resume = flags.resume;
  if (flags.validate) session.validation = flags.validation;
  session.validate_every = flags.validate_every;
  session.keep_validated = flags.keep_validated;
  session.validate();
  return session;
}

void run_train(TrainFlags& flags) {
  TrainingSessionOptions session = session_of(flags);
  session.threads = set_thread_count(flags.threads);
  TrainingSessionResult result;
  with_flag_names({{"train.batch", "batch"}}, [&] { result = run_training_session(session, Communicator::world()); });
  if (!Communicator::world().is_root()) return;
  if (result.out_of_time) {
    std::fprintf(stderr, "fnopt train: stopped after %.1f minutes at step %d; --resume continues\n", flags.minutes,
                 result.steps);
    return;
  }
  std::printf("trained %d steps in %s; model %s, log %s\n", result.steps, format_duration(result.seconds).c_str(),
              result.model_path.c_str(), result.log_path.c_str());
  if (result.best_step >= 0)
    std::printf("best validation: step %d, e_3D x 10^2 %.4g at %s (%s); model %s, log %s\n", result.best_step,
                result.best_e3d, RolloutValidation::grid_set_text(flags.validation, true).c_str(),
                result.validation_motions.c_str(), result.best_model_path.c_str(), result.validation_log_path.c_str());
}

// The loss: what a training step scores, and where the run starts from.
void add_objective_flags(CLI::App* command, TrainOptions& o) {
  command->add_option("--steps", o.steps, "training steps")->capture_default_str();
  command
      ->add_option("--objective", o.objective,
                   "what a step scores: energy, the energy after the learned update (the shipped model's "
                   "training); probe, the model as fnopt-pqn's probe: how much of the Newton step's decrease pqn's "
                   "next iterations (--probe-iterations) miss with the pair measured along the proposal (the pool "
                   "follows Newton's "
                   "solution; --newton-weight does not apply)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, TrainObjective>{{"energy", TrainObjective::Energy}, {"probe", TrainObjective::Probe}}))
      ->option_text("{energy,probe}=energy");
  command
      ->add_option("--probe-iterations", o.probe.iterations,
                   "probe objective: how many pqn iterations after the probe the loss scores (the share of the "
                   "decrease to the step's solution they miss)")
      ->capture_default_str();
  command
      ->add_option("--probe-surface", o.probe.surface,
                   "probe objective: what those iterations run on: model, the step's quadratic model (projected "
                   "Hessian; cheap); energy, the step's energy itself (the loss is then fnopt-pqn's per-step error; "
                   "a gradient per iteration, a Hessian per iteration in the backward pass)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, ProbeSurface>{{"model", ProbeSurface::QuadraticModel},
                                                                              {"energy", ProbeSurface::Energy}}))
      ->option_text("{model,energy}=model");
  command->add_option("--init", o.initial_model,
                      "start a fresh run from this model's weights (its shape replaces --width, --layers, --modes, "
                      "--lifting, --projection), e.g. models/fnopt-32.pt");
}

// The pool of environments and the optimiser's settings.
void add_pool_flags(CLI::App* command, TrainFlags& flags) {
  TrainOptions& o = flags.options;
  command->add_option("--batch", o.batch, "environments per step")->capture_default_str();
  command->add_option("--envs", o.pool.environments, "environments in the pool")->capture_default_str();
  command
      ->add_option("--res", o.pool.resolutions,
                   "training grid(s), N for N x N, comma-separated: environment e lives on the (e mod count)-th; "
                   "a count that divides --batch puts each grid in every batch alike (energy objective, "
                   "per-environment loss)")
      ->delimiter(',')
      ->capture_default_str();
  command
      ->add_option("--env-lifetime", o.pool.max_age,
                   "time steps an environment lives before a new one (material, pose, handles, motion) "
                   "replaces it")
      ->capture_default_str();
  command->add_option("--lr", o.learning_rate, "AdamW learning rate")->capture_default_str();
  command->add_option("--decay-every", o.decay_every, "halve the learning rate every N steps")->capture_default_str();
  command->add_option("--clip", o.clip_norm, "gradient-norm clipping")->capture_default_str();
  command->add_option("--seed", o.seed, "random seed")->capture_default_str();
  command
      ->add_option(
          "--newton-weight", o.newton_weight,
          "weight of the auxiliary loss toward the reference step (Newton's, or pqn's with --reference-pqn-iters)")
      ->capture_default_str();
  command
      ->add_option("--average-decay", o.average_decay,
                   "the model written and validated is the moving average of the trained weights, "
                   "w_avg <- d w_avg + (1 - d) w after every step; 0: the trained weights themselves")
      ->capture_default_str();
  command->add_option("--range", flags.ranges,
                      "sampling range of the pool, QUANTITY=LOW:HIGH, log-uniform, in grid units (repeatable): "
                      "stretch k~_s (default 40:8000), shear k~_sh (0.5:600), bend k~_b (0.005:20), gravity g~ "
                      "(0.03:0.6), damping c dt (0.005:0.3); docs/training.md, \"The training pool in numbers\"");
  command
      ->add_option("--subspace", o.pool.subspace,
                   "how the pool takes each proposal: 0, as it is (the shipped model's training); K, as fnopt-ss "
                   "does: the subspace step over the last K proposals, carried across time steps, and the energy "
                   "safeguard, so the model trains on the states it meets at inference")
      ->capture_default_str();
  command
      ->add_option("--score", o.score_after_subspace_step,
                   "where the loss scores each update: proposal, the energy at a + delta (the shipped model's "
                   "training); subspace-step, where the pool's rule ends after it, past the subspace step (needs "
                   "--subspace K), so a proposal is judged by what it adds to the directions kept")
      ->transform(CLI::CheckedTransformer(std::map<std::string, bool>{{"proposal", false}, {"subspace-step", true}}))
      ->option_text("{proposal,subspace-step}=proposal");
  command->add_flag("--pqn-direction", o.pool.pqn_direction,
                    "with --subspace K: the pool also puts pqn's preconditioned gradient -A^-1 g in the subspace "
                    "before each proposal, as fnopt does, and the validation runs fnopt: the model "
                    "trains for the directions that complement pqn's");
  command
      ->add_option("--reference-pqn-iters", o.pool.reference_pqn_iterations,
                   "the reference L* each time step's loss is measured against: 0, Newton's converged step (the "
                   "shipped model's training); K, K pqn iterations, an upper bound on L* that costs the same on every "
                   "material, for pools with fine grids, where Newton on the stiffest materials takes most of the time")
      ->capture_default_str();
  command->add_option("--undamped-share", o.pool.ranges.undamped_share, "share of the environments without damping")
      ->capture_default_str();
}

// The model's shape, checkpoints and the validation that keeps the best model.
void add_model_and_session_flags(CLI::App* command, const std::shared_ptr<TrainFlags>& flags) {
  command->add_option("--width", flags->width, "FNO width")->capture_default_str();
  command->add_option("--layers", flags->layers, "Fourier layers")->capture_default_str();
  command->add_option("--modes", flags->modes, "Fourier modes per axis")->capture_default_str();
  command->add_option("--lifting", flags->lifting, "lifting MLP width")->capture_default_str();
  command->add_option("--projection", flags->projection, "projection MLP width")->capture_default_str();
  command->add_option("--checkpoint-every", flags->checkpoint_every, "steps between checkpoints")
      ->capture_default_str();
  command->add_option("--minutes", flags->minutes, "stop (with a checkpoint) after this many minutes");
  add_threads_flag(*command, flags->threads);
  command->add_flag("--resume", flags->resume, "continue from OUT/checkpoint.pt");
  CLI::Option* validate_res =
      command
          ->add_option(
              "--validate-res", flags->validation.resolutions,
              "validate on N x N grid(s), comma-separated, every --validate-every steps: fnopt-ss rollouts of "
              "benchmark scenes (default material; --validate-motions, --validate-handles) against their Newton "
              "references (solved once, cached in OUT); the score is the mean e_3D over each grid's scenes (with "
              "several grids, the geometric mean of the grids' means); the closest model so far is kept as "
              "OUT/model-best.pt, each score in OUT/validation.csv. At 32^2 every motion with the corner handles is "
              "a scene of the 32^2 table: validate there off the corners (e.g. --validate-handles diagonal)")
          ->delimiter(',')
          ->each([flags](const std::string&) { flags->validate = true; });
  command->add_option("--validate-every", flags->validate_every, "steps between validations")
      ->capture_default_str()
      ->needs(validate_res);
  add_validation_scene_flags(*command, flags->validation, "validate-", validate_res);
  command
      ->add_flag("--keep-validated", flags->keep_validated,
                 "also keep every validated model as OUT/validated/model-STEP.pt (to compare them later)")
      ->needs(validate_res);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<TrainFlags>();
  CLI::App* command = app.add_subcommand("train", "meta-train a learned optimizer from the energy alone");
  command->add_option("--out", flags->out, "output folder: model.pt, checkpoint.pt, train_log.csv")->required();
  add_objective_flags(command, flags->options);
  add_pool_flags(command, *flags);
  add_model_and_session_flags(command, flags);
  command->callback([flags] { run_train(*flags); });
});

}  // namespace
}  // namespace fnopt::app
