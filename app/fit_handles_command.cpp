// fnopt fit-handles: flags only; the fit is fits/handle_path_fit_run.hpp (the handles' path that
// brings the cloth to a target shape, by the adjoint gradient and by a compass search, docs/design.md §15).
#include <fnopt/fits/handle_path_fit_run.hpp>
#include <fnopt/util/output_path.hpp>
#include "app/commands.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

// The default scene: gradcheck's, its handles moving within it (xy_v2 four times over), so that the
// cloth leaves its flat start, where a hanging sheet is unstable out of its plane and the step's
// derivative explodes (docs/design.md §15, "Branches"); a path offset then steers a moving cloth.
constexpr int kDefaultResolution = 12;
constexpr int kDefaultSteps = 40;
constexpr double kDefaultSpeed = 4.0;

struct FitHandlesFlags {
  SceneFlags scene;
  HandlePathFitRun run;
  int threads = 0;  // the default: set_thread_count
};

void run_fit_handles(FitHandlesFlags& flags) {
  flags.run.threads = set_thread_count(flags.threads);
  flags.run.validate();
  for (const auto& [path, flag] :
       {std::pair{&flags.run.csv, "csv"}, {&flags.run.plot, "plot"}, {&flags.run.out, "out"}})
    if (!path->empty()) require_writable_file(*path, flag);
  run_handle_path_fit(flags.run, flags.scene.scene_of_steps(kDefaultResolution, kDefaultSteps, kDefaultSpeed));
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<FitHandlesFlags>();
  HandlePathFitRun& run = flags->run;
  CLI::App* command = app.add_subcommand(
      "fit-handles",
      "find the handles' path that brings the cloth to a target shape, by the rollout's adjoint gradient and by "
      "a gradient-free compass search at the same budget (docs/design.md §15). Default scene: 12x12, 40 steps, "
      "corner handles, motion xy_v2 at speed 4; the target: a frame of --target, or the rollout of a hidden path");
  flags->scene.add_to(*command);
  command->add_option("--target", run.target,
                      "a rollout file (fnopt simulate --out) of the same grid whose frame is the target (default: "
                      "the rollout of a hidden path, see --hidden-scale)");
  command->add_option("--target-frame", run.target_frame, "the target frame (default: the scene's last)");
  command
      ->add_option("--hidden-scale", run.hidden_scale,
                   "without --target: the hidden path's control points are uniform within this many metres")
      ->capture_default_str();
  command->add_option("--hidden-seed", run.hidden_seed, "without --target: the hidden path's seed")
      ->capture_default_str();
  command->add_option("--method", run.method, "gradient, compass or both")->capture_default_str();
  command->add_option("--control-points", run.params.path.control_points, "control points per handle")
      ->capture_default_str();
  command->add_option("--basis", run.basis, "the path's curve: spline (cubic B-spline) or linear")
      ->capture_default_str();
  command->add_option("--bound", run.params.bound, "each control point coordinate within this many metres")
      ->capture_default_str();
  command
      ->add_option("--passes", run.params.passes,
                   "forward and backward passes per method (a gradient evaluation takes two, or one and two per "
                   "--samples with --smoothing)")
      ->capture_default_str();
  command
      ->add_option("--initial-step", run.params.initial_step,
                   "the first move [m]: the compass's first poll step, the largest coordinate of L-BFGS's first step")
      ->capture_default_str();
  command->add_option("--compass-final-step", run.params.compass_final_step, "compass: smallest step [m]")
      ->capture_default_str();
  command
      ->add_option("--smoothing", run.params.smoothing.sigma,
                   "gradient: minimise the loss averaged over perturbations of the control points of this many "
                   "metres (randomized smoothing; 0: the exact gradient), where a buckling cloth makes the exact "
                   "gradient hold only for tiny steps (docs/design.md §15)")
      ->capture_default_str();
  command->add_option("--samples", run.params.smoothing.samples, "with --smoothing: perturbations per evaluation (even)")
      ->capture_default_str();
  command->add_option("--csv", run.csv, "write the best loss against passes, per method, as CSV");
  command->add_option("--plot", run.plot, "draw the loss against passes as SVG");
  command->add_option("--out", run.out,
                      "write the fitted path (the first method's) as a trajectory CSV for --trajectory");
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_fit_handles(*flags); });
});

}  // namespace
}  // namespace fnopt::app
