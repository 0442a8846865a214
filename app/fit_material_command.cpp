// fnopt fit-material: flags only; the fit is fits/material_fit_run.hpp (by the rollout's adjoint
// gradient, docs/design.md §15, or by a compass search on e_CD).
#include <fnopt/fits/material_fit_run.hpp>
#include <fnopt/methods/thread_count.hpp>
#include <fnopt/util/output_path.hpp>
#include "app/commands.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct FitFlags {
  MaterialFitRun run;
  int threads = 0;  // the default: set_thread_count
};

void run_fit(FitFlags& flags) {
  require_writable_file(flags.run.out, "out");
  flags.run.threads = set_thread_count(flags.threads);
  run_material_fit(flags.run);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<FitFlags>();
  MaterialFitRun& run = flags->run;
  CLI::App* command = app.add_subcommand(
      "fit-material",
      "fit the material so that fnopt's exact (Newton) rollout reproduces reference rollouts (ARCSim files or "
      "fnopt rollouts), by the rollout's gradient or a compass search on e_CD; writes a material file for "
      "--material");
  command
      ->add_option("--reference", run.references, "reference rollout(s) to fit to (HDF5); the error is their mean")
      ->required()
      ->check(CLI::ExistingFile);
  command
      ->add_option("--check", run.checks,
                   "further references to report the fitted material's error on (e.g. other resolutions)")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--method", run.method,
                   "gradient: Levenberg-Marquardt in ln(coefficient) on the Gauss-Newton model of the rollout's "
                   "tangents (docs/design.md §15), minimising, per reference frame matched by time, the squared "
                   "distance of every vertex to its own (an fnopt rollout) or e_CD (an ARCSim file: --cd-samples, "
                   "--cd-stride), with each fitted value's uncertainty; compass: the compass search on e_CD")
      ->capture_default_str();
  command->add_option("--fit", run.coefficients,
                      "coefficients to fit: stretch, shear, bend, damping (default: all four). Positions determine "
                      "the stiffnesses only relative to the density, which stays the start's (or --mass's)");
  command->add_option("--mass", run.mass, "the cloth's mass in kg: sets the density (0: the start material's)")
      ->capture_default_str();
  command->add_option("--range", run.ranges,
                      "search interval COEFFICIENT=LOW:HIGH (defaults: stretch 1:800 N/m, shear 0.001:1e4 N/m, "
                      "bend 1e-9:0.01 N m, damping 0.001:100 1/s)");
  command
      ->add_option("--start", run.start,
                   "material to start from: a preset or a material file (the references' own material is never used)")
      ->capture_default_str();
  command->add_option("--horizons", run.horizons,
                      "gradient: fit first on these fractions of the steps, each stage from the last one's result, "
                      "then on all (a buckling cloth's late frames make the loss rough far from the fit); none: all "
                      "at once (default: 0.333)");
  command->add_option("--frames", run.params.frames, "time steps per rollout (0: the reference's whole duration)")
      ->capture_default_str();
  command->add_option("--max-evaluations", run.params.max_evaluations,
                      "Newton rollouts (compass) or evaluations (gradient: a forward and a tangent pass each) at "
                      "most, per reference set")
      ->capture_default_str();
  command
      ->add_option("--initial-step", run.params.initial_step,
                   "first step in ln(coefficient): compass, its first poll; gradient, the largest change of a "
                   "coefficient in its first step")
      ->capture_default_str();
  command->add_option("--final-step", run.params.final_step, "compass: stop when the step is below this")
      ->capture_default_str();
  command->add_option("--cd-samples", run.params.chamfer.samples, "points sampled per mesh for e_CD")
      ->capture_default_str();
  command->add_option("--cd-stride", run.params.chamfer_stride, "e_CD on every k-th matched frame")
      ->capture_default_str();
  command->add_option("--out", run.out, "material file to write")->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_fit(*flags); });
});

}  // namespace
}  // namespace fnopt::app
