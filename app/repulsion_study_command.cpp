// fnopt repulsion-study: its flags, turned into a RepulsionStudy (studies/repulsion/repulsion_study.hpp):
// self-repulsion off and on, on the handle presets whose cloth folds onto itself and on the corner
// control (the paper's Table 6.5).

#include <fnopt/studies/repulsion/repulsion_study.hpp>
#include <fnopt/util/command_line.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct StudyFlags {
  std::string out;
  std::string optimizers = "newton,fnopt";
  int frames = 390;
  int res = 32;
  std::string motion = "xy_v2";
  double stiffness = Material{}.repulsion_stiffness;
  int iterations = 0;
  std::string model;
  int threads = 0;  // the default: set_thread_count
  bool resume = false;
};

void run_study(const StudyFlags& flags) {
  require(!flags.out.empty(), "out", "an output directory is required");
  require(flags.frames >= 1, "frames", "must be at least 1");
  require(flags.res >= 3, "res", "the grid needs at least 3 vertices along each side");
  const std::vector<std::string> optimizers = name_list("optimizers", flags.optimizers);
  std::vector<OptimizerChoice> choices;
  for (const auto& name : optimizers) {  // fail on a bad name before any work
    OptimizerChoice choice;
    choice.name = name;
    choice.iterations = flags.iterations;
    choice.model = flags.model;
    choice.make();
    choices.push_back(choice);
  }
  Scene base;
  base.rows = base.cols = flags.res;
  base.frames = flags.frames;
  apply_scene_setting(base, "motion", flags.motion);
  apply_scene_setting(base, "repulsion-stiffness", number_text(flags.stiffness));
  base.validate();
  require_writable_directory(flags.out, "out");

  RepulsionStudy study;
  study.base = base;
  study.optimizers = choices;
  study.out = flags.out;
  study.command_line = process_command_line("fnopt repulsion-study");
  study.threads = set_thread_count(flags.threads);
  study.resume = flags.resume;
  run_repulsion_study(study);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<StudyFlags>();
  CLI::App* command = app.add_subcommand(
      "repulsion-study",
      "self-repulsion off and on for the folding presets (corner-center, single-mid-edge) and the corner control: "
      "repulsive energy and penetration proxies per rollout (CSV, SVG, report)");
  command
      ->add_option("--out", flags->out,
                   "output directory (repulsion.csv, repulsion_energy.csv, repulsion.svg, report.md)")
      ->required();
  command->add_option("--optimizers", flags->optimizers, "optimizers, comma-separated: " + optimizer_names())
      ->capture_default_str();
  command->add_option("--frames", flags->frames, "time steps per rollout")->capture_default_str();
  command->add_option("--res", flags->res, "grid resolution N (N x N)")->capture_default_str();
  command->add_option("--motion", flags->motion, "handle motion")->capture_default_str();
  command->add_option("--repulsion-stiffness", flags->stiffness, "lambda of the runs with repulsion on [N/m]")
      ->capture_default_str();
  command->add_option("--iters", flags->iterations, "iterations per step (default: each method's)");
  command->add_option("--model", flags->model, "learned optimizer weights (default: the shipped model)");
  add_threads_flag(*command, flags->threads);
  command->add_flag("--resume", flags->resume,
                    "keep the runs already in DIR/repulsion.csv (same preset, repulsion, optimizer) and run the rest");
  command->callback([flags] { run_study(*flags); });
});

}  // namespace
}  // namespace fnopt::app
