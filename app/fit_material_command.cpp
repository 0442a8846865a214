// fnopt fit-material: the stretch, shear, bend and damping whose exact (Newton) rollout best
// reproduces reference rollouts in e_CD (studies/material_fit.hpp). Prints each
// evaluation, the fitted values and their error against the start material's, optionally the
// error on further references (--check: how the fit transfers to other resolutions), and writes a
// material file for --material.
#include <cmath>
#include <cstdio>

#include <fnopt/studies/material_fit.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include "app/commands.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct FitFlags {
  std::vector<std::string> references;
  std::vector<std::string> checks;
  std::string coefficients = "stretch,shear,bend,damping";
  std::string start = "default";
  std::vector<std::string> ranges;
  std::string out = "fitted-material.txt";
  MaterialFitParams params;
  int threads = 0;  // the default: set_thread_count
};

std::string material_text(const Material& m) {
  char text[200];
  std::snprintf(text, sizeof text, "stretch %.4g N/m, shear %.4g N/m, bend %.4g N m, damping %.4g 1/s", m.stretch,
                m.shear, m.bend, m.damping);
  return text;
}

std::string errors_text(const FitEvaluation& e) {
  std::string text;
  for (double error : e.errors) text += (text.empty() ? "" : ", ") + number_text(1e3 * error);
  return text;
}

std::vector<FitReference> load_references(const std::vector<std::string>& paths) {
  std::vector<FitReference> references;
  for (const auto& path : paths) references.push_back(load_fit_reference(path));
  return references;
}

void run_fit(FitFlags& flags) {
  require_writable_file(flags.out, "out");
  const int threads = set_thread_count(flags.threads);
  flags.params.coefficients.clear();
  for (auto name : split(flags.coefficients, ','))
    flags.params.coefficients.push_back(material_coefficient(std::string(trim(name))));
  for (const auto& text : flags.ranges) {
    std::string name;
    CoefficientRange range;
    require(parse_named_interval(text, name, range.low, range.high), "range",
            "expected COEFFICIENT=LOW:HIGH, got '" + text + "'");
    flags.params.range(material_coefficient(name)) = range;
  }
  with_flag_names({{"fit.coefficients", "fit"},
                   {"fit.initial_step", "initial-step"},
                   {"fit.final_step", "final-step"},
                   {"fit.max_evaluations", "max-evaluations"},
                   {"fit.frames", "frames"},
                   {"fit.chamfer_stride", "cd-stride"},
                   {"chamfer.samples", "cd-samples"},
                   {"fit.stretch_range", "range"},
                   {"fit.shear_range", "range"},
                   {"fit.bend_range", "range"},
                   {"fit.damping_range", "range"}},
                  [&] { flags.params.validate(); });
  const Material start = material_preset(flags.start);
  const auto references = load_references(flags.references);
  for (const auto& r : references)
    std::printf("reference %s: %dx%d, motion %s, %d steps of %.4g s\n", r.path.c_str(), r.scene.rows, r.scene.cols,
                r.scene.motion.c_str(), flags.params.frames > 0 ? flags.params.frames : r.scene.frames, r.scene.dt);
  std::printf(
      "fitting %s from %s (%s); compass search in ln(coefficient), step %.3g down to %.3g, at most %d "
      "Newton rollouts per reference; %d thread%s\n",
      flags.coefficients.c_str(), flags.start.c_str(), material_text(start).c_str(), flags.params.initial_step,
      flags.params.final_step, flags.params.max_evaluations, threads, threads == 1 ? "" : "s");

  ProgressBar bar("fit", flags.params.max_evaluations);
  const MaterialFitResult result =
      fit_material(references, start, flags.params, [&](int k, const FitEvaluation& e, const FitEvaluation& best) {
        bar.update(k, "best e_CD x1e3 " + number_text(1e3 * best.mean_error));
        std::printf("\n  %3d  %s  ->  e_CD x 10^3 = %s\n", k, material_text(e.material).c_str(),
                    number_text(1e3 * e.mean_error).c_str());
        std::fflush(stdout);
      });
  bar.finish();

  std::printf("fitted:  %s\n", material_text(result.best.material).c_str());
  std::printf("e_CD x 10^3: %s (mean %s) against %s (mean %s) for the start material; %d rollouts per reference, %s\n",
              errors_text(result.best).c_str(), number_text(1e3 * result.best.mean_error).c_str(),
              errors_text(result.start).c_str(), number_text(1e3 * result.start.mean_error).c_str(), result.evaluations,
              result.converged ? "converged (step below the final step)" : "stopped at --max-evaluations");
  if (!flags.checks.empty()) {
    const auto checks = load_references(flags.checks);
    for (const auto& reference : checks) {
      const auto fitted = evaluate_material({reference}, result.best.material, flags.params);
      const auto before = evaluate_material({reference}, start, flags.params);
      std::printf("check %s (%dx%d, %s): e_CD x 10^3 = %s fitted, %s start material\n", reference.path.c_str(),
                  reference.scene.rows, reference.scene.cols, reference.scene.motion.c_str(),
                  number_text(1e3 * fitted.mean_error).c_str(), number_text(1e3 * before.mean_error).c_str());
    }
  }
  std::string comment = "fitted by fnopt fit-material (" + flags.coefficients + ") to";
  for (const auto& path : flags.references) comment += "\n  " + path;
  comment += "\ne_CD x 10^3 = " + number_text(1e3 * result.best.mean_error) +
             " (start material: " + number_text(1e3 * result.start.mean_error) + ")";
  write_material_file(flags.out, result.best.material, comment);
  std::printf("wrote %s (use it with --material %s)\n", flags.out.c_str(), flags.out.c_str());
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<FitFlags>();
  CLI::App* command = app.add_subcommand(
      "fit-material",
      "fit stretch, shear, bend and damping so that fnopt's exact (Newton) rollout reproduces reference rollouts "
      "(ARCSim files or fnopt rollouts) in e_CD; writes a material file for --material");
  command
      ->add_option("--reference", flags->references, "reference rollout(s) to fit to (HDF5); the error is their mean")
      ->required()
      ->check(CLI::ExistingFile);
  command
      ->add_option("--check", flags->checks,
                   "further references to report the fitted material's error on (e.g. other resolutions)")
      ->check(CLI::ExistingFile);
  command->add_option("--fit", flags->coefficients, "coefficients to fit: stretch, shear, bend, damping")
      ->capture_default_str();
  command->add_option("--range", flags->ranges,
                      "search interval COEFFICIENT=LOW:HIGH (defaults: stretch 1:800 N/m, shear 0.001:1e4 N/m, "
                      "bend 1e-9:0.01 N m, damping 0.001:100 1/s)");
  command->add_option("--start", flags->start, "material to start from: a preset or a material file")
      ->capture_default_str();
  command->add_option("--frames", flags->params.frames, "time steps per rollout (0: the reference's whole duration)")
      ->capture_default_str();
  command->add_option("--max-evaluations", flags->params.max_evaluations, "Newton rollouts at most")
      ->capture_default_str();
  command->add_option("--initial-step", flags->params.initial_step, "first search step in ln(coefficient)")
      ->capture_default_str();
  command->add_option("--final-step", flags->params.final_step, "stop when the step is below this")
      ->capture_default_str();
  command->add_option("--cd-samples", flags->params.chamfer.samples, "points sampled per mesh for e_CD")
      ->capture_default_str();
  command->add_option("--cd-stride", flags->params.chamfer_stride, "e_CD on every k-th matched frame")
      ->capture_default_str();
  command->add_option("--out", flags->out, "material file to write")->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_fit(*flags); });
});

}  // namespace
}  // namespace fnopt::app
