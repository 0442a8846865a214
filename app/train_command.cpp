// fnopt train: meta-train a learned optimizer (DESIGN.md §5) with progress, a CSV log,
// checkpoints and --resume.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/commands.hpp"
#include "app/threads.hpp"
#include "fno/fno_io.hpp"
#include "optimizer/learned/meta_trainer.hpp"
#include "util/atomic_file.hpp"
#include "util/error.hpp"
#include "util/progress_bar.hpp"

namespace fnopt::app {
namespace {

struct TrainFlags {
  TrainOptions options;
  std::string out;
  int checkpoint_every = 100;
  double minutes = 0.0;
  int threads = 0;
  bool resume = false;
  int64_t width = 32, layers = 4, modes = 8, lifting = 64, projection = 32;
  bool combined = false;
};

constexpr const char* kLogHeader =
    "step,seconds,loss,newton_loss,mean_ratio,gradient_norm,learning_rate,renewed,skipped";

// Keeps the log's rows up to `step` (those the checkpoint had seen) and returns the seconds
// already spent, so a resumed run's log reads as one run.
double trim_log(const std::string& path, int step) {
  std::ifstream in(path);
  std::ostringstream kept;
  kept << kLogHeader << '\n';
  std::string line;
  double seconds = 0.0;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string row_step, row_seconds;
    std::getline(fields, row_step, ',');
    std::getline(fields, row_seconds, ',');
    if (row_step.empty() || std::stoi(row_step) > step) break;
    seconds = std::stod(row_seconds);
    kept << line << '\n';
  }
  in.close();
  write_text_atomically(path, kept.str());
  return seconds;
}

void run_train(TrainFlags& flags) {
  flags.options.model.width(flags.width).fourier_layers(flags.layers).modes_x(flags.modes).modes_y(flags.modes)
      .lifting_channels(flags.lifting).projection_channels(flags.projection)
      .in_channels(flags.combined ? 9 : 3).out_channels(flags.combined ? 3 : 1);
  const int threads = set_thread_count(flags.threads);
  std::filesystem::create_directories(flags.out);
  const std::string checkpoint = (std::filesystem::path(flags.out) / "checkpoint.pt").string();
  const std::string model_path = (std::filesystem::path(flags.out) / "model.pt").string();
  const std::string log_path = (std::filesystem::path(flags.out) / "train_log.csv").string();

  const bool resuming = flags.resume && std::filesystem::exists(checkpoint);
  MetaTrainer trainer(flags.options, resuming ? checkpoint : std::string());
  double seconds_before = 0.0;
  if (resuming) {
    seconds_before = trim_log(log_path, trainer.completed_steps());
    std::fprintf(stderr, "fnopt train: resumed %s at step %d\n", checkpoint.c_str(), trainer.completed_steps());
  } else {
    require(!std::filesystem::exists(checkpoint) || flags.resume, "out",
            checkpoint + " exists: pass --resume to continue it, or choose another --out");
    std::ofstream(log_path) << kLogHeader << '\n';
  }
  std::fprintf(stderr, "fnopt train: %s, %d thread%s, writing %s\n", flags.options.signature().c_str(), threads,
               threads == 1 ? "" : "s", flags.out.c_str());

  std::ofstream log(log_path, std::ios::app);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  ProgressBar bar("train", flags.options.steps, trainer.completed_steps());
  double running_loss = NAN, running_ratio = NAN;
  auto save = [&] {
    trainer.save_checkpoint(checkpoint);
    save_fno(model_path, trainer.model());
  };
  while (trainer.completed_steps() < flags.options.steps) {
    const TrainStepStats s = trainer.step();
    const int step = trainer.completed_steps();
    running_loss = std::isfinite(running_loss) ? 0.98 * running_loss + 0.02 * s.loss : s.loss;
    if (std::isfinite(s.mean_ratio))
      running_ratio = std::isfinite(running_ratio) ? 0.98 * running_ratio + 0.02 * s.mean_ratio : s.mean_ratio;
    log << step << ',' << seconds_before + elapsed() << ',' << s.loss << ',' << s.newton_loss << ',' << s.mean_ratio << ',' << s.gradient_norm
        << ',' << s.learning_rate << ',' << s.renewed << ',' << s.skipped << '\n';
    char status[96];
    std::snprintf(status, sizeof status, "loss %.4f ratio %.4f lr %.1e", running_loss, running_ratio, s.learning_rate);
    bar.update(step, status);
    const bool out_of_time = flags.minutes > 0 && elapsed() > 60.0 * flags.minutes;
    if (step % flags.checkpoint_every == 0 || step == flags.options.steps || out_of_time) {
      log.flush();
      save();
    }
    if (out_of_time) {
      bar.finish();
      std::fprintf(stderr, "fnopt train: stopped after %.1f minutes at step %d; --resume continues\n", flags.minutes,
                   step);
      return;
    }
  }
  bar.finish();
  std::printf("trained %d steps in %s; model %s, log %s\n", trainer.completed_steps(),
              format_duration(seconds_before + elapsed()).c_str(), model_path.c_str(), log_path.c_str());
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<TrainFlags>();
  TrainOptions& o = flags->options;
  CLI::App* command = app.add_subcommand("train", "meta-train a learned optimizer from the energy alone");
  command->add_option("--out", flags->out, "output folder: model.pt, checkpoint.pt, train_log.csv")->required();
  command->add_option("--steps", o.steps, "training steps")->capture_default_str();
  command->add_option("--batch", o.batch, "environments per step")->capture_default_str();
  command->add_option("--envs", o.pool.environments, "environments in the pool")->capture_default_str();
  command->add_option("--res", o.pool.resolution, "training resolution")->capture_default_str();
  command->add_option("--lr", o.learning_rate, "AdamW learning rate")->capture_default_str();
  command->add_option("--decay-every", o.decay_every, "halve the learning rate every N steps")->capture_default_str();
  command->add_option("--clip", o.clip_norm, "gradient-norm clipping")->capture_default_str();
  command->add_option("--seed", o.seed, "random seed")->capture_default_str();
  command->add_option("--newton-weight", o.newton_weight, "weight of the auxiliary loss toward the Newton step")
      ->capture_default_str();
  command->add_option("--loss-normalisation", o.loss_normalisation,
                      "per-environment: the mean of each environment's remaining-error ratio; batch: one ratio "
                      "for the batch (FNOpt's mean energy, rescaled)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, LossNormalisation>{
          {"per-environment", LossNormalisation::PerEnvironment}, {"batch", LossNormalisation::Batch}}))
      ->option_text("{per-environment,batch}=per-environment");
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
  command->add_option("--threads", flags->threads, "threads (default: all cores)");
  command->add_flag("--resume", flags->resume, "continue from OUT/checkpoint.pt");
  command->callback([flags] { run_train(*flags); });
});

}  // namespace
}  // namespace fnopt::app
