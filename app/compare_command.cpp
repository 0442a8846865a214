// fnopt compare: its flags, turned into a CompareStudy (studies/compare/compare_study.hpp) that runs
// every inner optimizer on the same scenes, error against run time (docs/design.md §8, §10).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/studies/compare/compare_study.hpp>
#include <fnopt/util/command_line.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct CompareFlags {
  SceneFlags scene;
  std::string resolutions = "32";
  std::string motions = "xy_v2";
  std::string optimizers = "gd,adam,lbfgs,lbfgs-ls,newton";
  std::string iters = "10,100,500";
  std::vector<std::string> iters_for;  // METHOD=N,N,...
  std::string lr_gd = "0.25,0.5,1,1.5,1.9";
  std::string lr_adam = "0.0003,0.001,0.003,0.01";
  OptimizerChoice settings;  // --model and the other per-method settings
  std::string out;
  std::string arcsim_dir;
  std::string reference = "newton";
  std::string error_levels = "1,0.3,0.1";  // e_CD x 10^3
  std::string preset;
  int preset_frames = 0;  // the preset's frame count, where --frames was not given
  int threads = 0;        // the default: set_thread_count
  int step_samples = 16;
  int cd_samples = 10000;
  int cd_stride = 2;
  bool warm_start = false;
  bool keep_rollouts = false;
  bool resume = false;
};

std::vector<int> int_list(const std::string& flag, const std::string& text) {
  std::vector<int> values;
  for (auto piece : split(text, ',')) {
    int value = 0;
    require(parse_int(piece, value) && value > 0, flag, "expected positive integers 'a,b,c', got '" + text + "'");
    values.push_back(value);
  }
  return values;
}

std::vector<double> number_list(const std::string& flag, const std::string& text) {
  std::vector<double> values;
  for (auto piece : split(text, ',')) {
    double value = 0.0;
    require(parse_double(piece, value) && std::isfinite(value) && value > 0.0, flag,
            "expected positive numbers 'a,b,c', got '" + text + "'");
    values.push_back(value);
  }
  return values;
}

// --res: "N" (N x N) or "RxC" (R rows x C columns), comma-separated.
std::vector<GridSize> resolution_list(const std::string& text) {
  std::vector<GridSize> sizes;
  const std::string expected =
      "expected resolutions N (N x N) or RxC (R rows x C columns), comma-separated, e.g. "
      "'32,64,32x64', got '" +
      text + "'";
  for (auto piece : split(text, ',')) {
    const std::string item(trim(piece));
    const auto x = item.find_first_of("xX");
    GridSize size;
    if (x == std::string::npos) {
      require(parse_int(item, size.rows) && size.rows > 0, "res", expected);
      size.cols = size.rows;
    } else {
      require(parse_int(item.substr(0, x), size.rows) && parse_int(item.substr(x + 1), size.cols) && size.rows > 0 &&
                  size.cols > 0,
              "res", expected);
    }
    sizes.push_back(size);
  }
  return sizes;
}

// --preset superres: the zero-shot super-resolution study. Explicit flags win.
struct Preset {
  const char* resolutions;
  const char* optimizers;
  const char* iters;
  const char* iters_for;  // "" for none
  const char* motions;
  int frames;
  int step_samples;
};

// The learned optimizers (fnopt, fnopt-ss), each against its own interpolation from 32 vertices,
// fnopt-ss on the 32^2-only model (fnopt-ss-32: the zero-shot study proper), and the exact coarse
// step interpolated. Every grid is finer than 32 along its longer
// edge: an interpolation from 32 is refused on the 32 x 32 grid.
const Preset kSuperres = {"32x64,64x32,48,48x80,64,100,128",
                          "fnopt,fnopt-ss,fnopt-ss-32,fnopt-interp32,fnopt-ss-interp32,newton-interp32",
                          "10",
                          "newton-interp32=300",
                          "xy_v2",
                          30,
                          8};

// The scenes of every resolution and motion; a trajectory file replaces the motion list.
std::vector<Scene> scenes_of(const CompareFlags& flags) {
  const std::vector<GridSize> resolutions = resolution_list(flags.resolutions);
  const std::vector<std::string> motions =
      flags.motions == "eval" ? benchmark_motion_names() : name_list("motions", flags.motions);
  Scene base = flags.scene.scene();
  if (flags.preset_frames > 0) base.frames = flags.preset_frames;
  return compare_scenes(base, resolutions, motions);
}

void run_compare(const CompareFlags& flags) {
  CompareStudy study;
  study.scenes = scenes_of(flags);
  study.methods = name_list("optimizers", flags.optimizers);
  study.budgets = int_list("iters", flags.iters);
  for (const std::string& entry : flags.iters_for) {  // later entries win
    const auto equals = entry.find('=');
    require(equals != std::string::npos, "iters-for", "expected METHOD=N,N,..., got '" + entry + "'");
    study.budgets_for[std::string(trim(entry.substr(0, equals)))] = int_list("iters-for", entry.substr(equals + 1));
  }
  study.settings = flags.settings;
  study.learning_rates = {{"gd", number_list("lr-gd", flags.lr_gd)}, {"adam", number_list("lr-adam", flags.lr_adam)}};
  study.out = flags.out;
  study.arcsim_dir = flags.arcsim_dir;
  study.reference = flags.reference;
  study.preset = flags.preset;
  study.resolutions_text = flags.resolutions;
  study.command_line = process_command_line("fnopt compare");
  study.error_levels = number_list("error-levels", flags.error_levels);
  for (double& level : study.error_levels) level *= 1e-3;  // given as e_CD x 10^3
  study.chamfer.samples = flags.cd_samples;
  study.cd_stride = flags.cd_stride;
  study.step_samples = flags.step_samples;
  study.warm_start = flags.warm_start;
  study.keep_rollouts = flags.keep_rollouts;
  study.resume = flags.resume;
  with_flag_names({{"compare.scenes", "res"},
                   {"compare.methods", "optimizers"},
                   {"compare.out", "out"},
                   {"compare.budgets", "iters"},
                   {"compare.budgets_for", "iters-for"},
                   {"compare.learning_rates", "optimizers"},
                   {"compare.error_levels", "error-levels"},
                   {"compare.cd_stride", "cd-stride"},
                   {"compare.step_samples", "step-samples"}},
                  [&] { study.validate(); });
  require_writable_directory(flags.out, "out");
  study.threads = set_thread_count(flags.threads);
  run_compare_study(study);
}

// The learning rates, method settings, outputs and measurement flags.
void add_output_flags(CLI::App* command, CompareFlags& flags) {
  command
      ->add_option("--lr-gd", flags.lr_gd,
                   "gd learning rates (x 1/lambda_max); several: the best per budget on the first scene")
      ->capture_default_str();
  command
      ->add_option("--lr-adam", flags.lr_adam,
                   "adam learning rates (cell widths per step^2); several: the best per budget on the first scene")
      ->capture_default_str();
  add_method_setting_flags(*command, flags.settings);
  command->add_option("--out", flags.out, "output directory (CSV, SVG, cached references)")->required();
  command
      ->add_option("--error-levels", flags.error_levels,
                   "e_CD x 10^3 levels at which the fastest method is printed (and in report.md)")
      ->capture_default_str();
  command
      ->add_option("--reference", flags.reference,
                   "the rollout every error is measured against: newton (the exact step), or newton-min, which "
                   "leaves saddles and ends at minima: the reference off the corner presets (docs/design.md §6)")
      ->check(CLI::IsMember({"newton", "newton-min"}))
      ->capture_default_str();
  command->add_option("--arcsim-dir", flags.arcsim_dir,
                      "also report e_CD against DIR/arcsim_N{res}_{motion}.h5 where it exists");
  add_threads_flag(*command, flags.threads);
  command->add_option("--step-samples", flags.step_samples, "reference states for the per-step error")
      ->capture_default_str();
  command->add_option("--cd-samples", flags.cd_samples, "points sampled per mesh for e_CD")->capture_default_str();
  command->add_flag("--warm-start", flags.warm_start, "start each step from the previous step's acceleration");
  command->add_flag("--keep-rollouts", flags.keep_rollouts, "also write every rollout to DIR");
  command->add_flag("--resume", flags.resume,
                    "keep the runs already in DIR/compare.csv (same method, N, resolution, motion) and run the rest");
  command
      ->add_option("--cd-stride", flags.cd_stride,
                   "e_CD on every k-th matched frame (2: every 1/30 s at dt = 1/60, as the ARCSim files)")
      ->capture_default_str();
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<CompareFlags>();
  CLI::App* command =
      app.add_subcommand("compare", "every optimizer on the same scenes: error against run time (CSV + SVG plot)");
  flags->scene.add_to(*command, /*with_resolution=*/false);
  CLI::Option* res = command->add_option(
      "--res", flags->resolutions,
      "resolutions, comma-separated: N (N x N) or RxC (R rows x C columns, the longer edge 1 m), e.g. 32,64,32x64");
  res->capture_default_str();
  CLI::Option* motions =
      command->add_option("--motions", flags->motions, "motions, comma-separated, or 'eval' (the fifteen)");
  motions->capture_default_str();
  CLI::Option* optimizers =
      command->add_option("--optimizers", flags->optimizers, "optimizers, comma-separated: " + optimizer_names());
  optimizers->capture_default_str();
  CLI::Option* iters = command->add_option("--iters", flags->iters, "iteration budgets per time step, comma-separated");
  iters->capture_default_str();
  CLI::Option* iters_for = command->add_option(
      "--iters-for", flags->iters_for, "budgets of one method, overriding --iters: METHOD=N,N,... (repeatable)");
  command
      ->add_option(
          "--preset", flags->preset,
          "a prepared study; its values give way to the flags given. 'superres': zero-shot super-resolution: "
          "--res " +
              std::string(kSuperres.resolutions) + " --optimizers " + kSuperres.optimizers + " --iters " +
              kSuperres.iters + " --iters-for " + kSuperres.iters_for + " --motions " + kSuperres.motions +
              " --frames " + std::to_string(kSuperres.frames) + " --step-samples " +
              std::to_string(kSuperres.step_samples) + " (the first " + number_text(kSuperres.frames / 60.0) +
              " s of the motion at dt = 1/60, the handles' first swing; the fine-grid Newton references dominate the "
              "cost, ~1 s of CPU per frame at 100^2; for more frames give --frames and a new --out: --resume keeps "
              "rows by method, N, resolution and motion only); the "
              "fine grid runs fnopt (on the 32^2-only model), fnopt-ss (by default on the multi-resolution model) and "
              "fnopt-ss-32 (on the 32^2-only model) against "
              "METHOD-interp32 (solve at 32 vertices along the longer edge, interpolate) and newton-interp32 (exact "
              "coarse step, interpolate); "
              "also writes superres.svg and a super-resolution table in report.md")
      ->check(CLI::IsMember({"superres"}));
  add_output_flags(command, *flags);
  CLI::Option* step_samples = command->get_option("--step-samples");
  CLI::Option* frames = command->get_option("--frames");
  command->callback([flags, res, motions, optimizers, iters, iters_for, frames, step_samples] {
    if (flags->preset == "superres") {
      const Preset& p = kSuperres;
      if (res->count() == 0) flags->resolutions = p.resolutions;
      if (motions->count() == 0) flags->motions = p.motions;
      if (optimizers->count() == 0) flags->optimizers = p.optimizers;
      if (iters->count() == 0) flags->iters = p.iters;
      // The preset's budget of a method stays unless --iters-for names that method (later
      // entries win in run_compare).
      const std::string preset_entry = p.iters_for;
      const auto chosen = name_list("optimizers", flags->optimizers);
      if (!preset_entry.empty() &&
          std::find(chosen.begin(), chosen.end(), preset_entry.substr(0, preset_entry.find('='))) != chosen.end())
        flags->iters_for.insert(flags->iters_for.begin(), preset_entry);
      if (frames->count() == 0) flags->preset_frames = p.frames;
      if (step_samples->count() == 0) flags->step_samples = p.step_samples;
    }
    run_compare(*flags);
  });
});

}  // namespace
}  // namespace fnopt::app
