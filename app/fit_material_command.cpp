// fnopt fit-material: the material whose exact (Newton) rollout best reproduces reference
// rollouts. Two methods: by the rollout's adjoint gradient (the default; docs/design.md §15), a
// bounded L-BFGS in the logarithms of the coefficients on e_CD and its gradient, or by the
// compass search on e_CD (studies/material_fit.hpp). Prints each evaluation, the
// fitted values and their e_CD against the start material's, optionally the error on further
// references (--check: how the fit transfers to other resolutions), and writes a material file
// for --material.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/adjoint/bounded_lbfgs.hpp>
#include <fnopt/adjoint/material_gradient.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/metrics/frame_matching.hpp>
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
  std::string method = "gradient";
  int iterations = 30;  // gradient: L-BFGS iterations at most
  std::vector<std::string> references;
  std::vector<std::string> checks;
  std::string coefficients;  // default: stretch,shear,bend,damping (compass), stretch,shear,damping (gradient)
  std::string start = "default";
  std::vector<std::string> ranges;
  std::string out = "fitted-material.txt";
  MaterialFitParams params;
  int threads = 0;  // the default: set_thread_count
};

std::string material_text(const Material& m) {
  char text[240];
  std::snprintf(text, sizeof text,
                "stretch %.4g N/m, shear %.4g N/m, bend %.4g N m, density %.4g kg/m^2, damping %.4g 1/s", m.stretch,
                m.shear, m.bend, m.density, m.damping);
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

// --check: the fitted and the start material's e_CD on further references.
void report_checks(const FitFlags& flags, const Material& fitted_material, const Material& start) {
  for (const auto& reference : load_references(flags.checks)) {
    const auto fitted = evaluate_material({reference}, fitted_material, flags.params);
    const auto before = evaluate_material({reference}, start, flags.params);
    std::printf("check %s (%dx%d, %s): e_CD x 10^3 = %s fitted, %s start material\n", reference.path.c_str(),
                reference.scene.rows, reference.scene.cols, reference.scene.motion.c_str(),
                number_text(1e3 * fitted.mean_error).c_str(), number_text(1e3 * before.mean_error).c_str());
  }
}

// The material file, its comment saying how it was fitted.
void write_fit(const FitFlags& flags, const Material& material, const FitEvaluation& fitted,
               const FitEvaluation& start) {
  std::string comment = "fitted by fnopt fit-material --method " + flags.method + " (" + flags.coefficients + ") to";
  for (const auto& path : flags.references) comment += "\n  " + path;
  comment += "\ne_CD x 10^3 = " + number_text(1e3 * fitted.mean_error) +
             " (start material: " + number_text(1e3 * start.mean_error) + ")";
  write_material_file(flags.out, material, comment);
  std::printf("wrote %s (use it with --material %s)\n", flags.out.c_str(), flags.out.c_str());
}

// A reference's frames as the gradient method's loss reads them: the rollout frame f (time f dt
// after the reference's first) matched to each reference frame by time (metrics/frame_matching.hpp).
// An fnopt rollout on the scene's grid gives every vertex's target after the initial frame (a
// position loss); an ARCSim file gives e_CD itself (adjoint/rollout_loss.hpp's
// surface_chamfer_loss): the reference mesh's samples on the matched frames e_CD reads, every
// --cd-stride-th from the first, so that the loss is the objective the compass search minimises.
struct GradientReference {
  ResolvedScene scene;  // with the start material; frames = the rollout's frame count
  bool positions = false;
  std::vector<FramePositions> targets;
  std::vector<FramePoints> points;
  std::size_t matched = 0;  // reference frames matched by time, the initial one included
};

GradientReference gradient_reference(const FitReference& reference, const Material& start,
                                     const MaterialFitParams& params) {
  GradientReference r;
  Scene scene = reference.scene;
  scene.material = start;  // never the reference's own
  if (params.frames > 0) scene.frames = params.frames;
  scene.frames += 1;  // the recorded rollout counts the initial frame
  r.scene = resolve(scene);
  r.positions = Hdf5File(reference.path, Hdf5File::Mode::Read).has_attribute("scene");
  std::vector<double> times(scene.frames);
  for (int f = 0; f < scene.frames; ++f) times[f] = reference.frames.times.front() + f * scene.dt;
  Grid reference_grid;
  reference_grid.rows = reference.frames.rows;
  reference_grid.cols = reference.frames.cols;
  const Triangles triangles = reference_grid.triangles();
  const std::vector<FrameMatch> matches = match_frames(reference.frames.times, times);
  r.matched = matches.size();
  for (std::size_t k = 0; k < matches.size(); ++k) {
    const FrameMatch& match = matches[k];
    const Eigen::VectorXf& x = reference.frames.positions[match.reference];
    if (r.positions && match.rollout > 0) r.targets.push_back({match.rollout, x.cast<double>()});
    if (!r.positions && k % params.chamfer_stride == 0)
      r.points.push_back({match.rollout, sample_mesh_surface(x.cast<double>(), triangles, params.chamfer.samples,
                                                             params.chamfer.seed)});
  }
  require(!r.targets.empty() || !r.points.empty(), reference.path,
          "no frame after the first matches the rollout's times");
  return r;
}

struct GradientFit {
  Material material;
  double start_loss = 0.0, loss = 0.0;
  BoundedLbfgsStatus status = BoundedLbfgsStatus::IterationBudget;
  int iterations = 0;
  int rollouts = 0;  // recorded forward passes, each with its backward pass
};

// Bounded L-BFGS (adjoint/bounded_lbfgs.hpp) in ln k of the fitted coefficients, within their
// --range intervals, on the mean over references of each one's loss; one recorded forward and one
// backward pass per reference and evaluation. A trial material whose rollout diverges has an
// infinite loss, which the line search steps back from.
GradientFit fit_by_gradient(const std::vector<GradientReference>& references, const Material& start,
                            const std::vector<AdjointParameter>& fit,
                            const std::map<AdjointParameter, CoefficientRange>& ranges, int iterations,
                            double first_step, const ChamferOptions& chamfer) {
  const Eigen::Index n = static_cast<Eigen::Index>(fit.size());
  VecX x0(n), lower(n), upper(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const CoefficientRange& range = ranges.at(fit[i]);
    lower[i] = std::log(range.low);
    upper[i] = std::log(range.high);
    Material m = start;
    x0[i] = std::clamp(std::log(material_coefficient(m, fit[i])), lower[i], upper[i]);
  }
  const auto material_at = [&](const VecX& x) {
    Material m = start;
    for (Eigen::Index i = 0; i < n; ++i) material_coefficient(m, fit[i]) = std::exp(x[i]);
    return m;
  };
  GradientFit result;
  const BoundedObjective objective = [&](const VecX& x, VecX& gradient) {
    const Material material = material_at(x);
    gradient = VecX::Zero(n);
    double value = 0.0;
    for (const GradientReference& reference : references) {
      ResolvedScene scene = reference.scene;
      scene.scene.material = material;
      const RecordedRollout rollout = record_rollout(scene);
      ++result.rollouts;
      if (rollout.diverged) {
        value = std::numeric_limits<double>::infinity();
        break;
      }
      const RolloutLoss loss = reference.positions ? position_loss(rollout, reference.targets)
                                                   : surface_chamfer_loss(rollout, reference.points, chamfer);
      const RolloutGradient adjoint = backpropagate(rollout, loss.gradient);
      value += loss.value / references.size();
      for (Eigen::Index i = 0; i < n; ++i) gradient[i] += adjoint.log_material.coefficient(fit[i]) / references.size();
    }
    std::printf("  %3d  %s  ->  loss %s\n", result.rollouts / static_cast<int>(references.size()),
                material_text(material).c_str(), number_text(value).c_str());
    std::fflush(stdout);
    if (result.rollouts == static_cast<int>(references.size())) result.start_loss = value;
    return value;
  };
  BoundedLbfgsParams params;
  params.max_iterations = iterations;
  // Where the rollout passes saddle steps the loss is rough at the scale of the solver's precision
  // near the fit (docs/design.md §15): a search that cannot descend there would take 30 halvings,
  // a rollout each, before it says so, and one that still can gains nothing a fit can use.
  params.max_backtracks = 10;
  params.relative_decrease = 1e-4;
  // The first step as the compass search's: the gradient's size says nothing about how far to go.
  params.first_step = first_step;
  const BoundedLbfgsResult fit_result = minimize_in_box(objective, x0, lower, upper, params);
  result.material = material_at(fit_result.x);
  result.loss = fit_result.value;
  result.status = fit_result.status;
  result.iterations = fit_result.iterations;
  return result;
}

// The gradient method's coefficients and their intervals: the compass's --range defaults, and
// density's; --range entries override them.
std::map<AdjointParameter, CoefficientRange> gradient_ranges(const FitFlags& flags) {
  const MaterialFitParams defaults;
  std::map<AdjointParameter, CoefficientRange> ranges = {{AdjointParameter::Stretch, defaults.stretch_range},
                                                         {AdjointParameter::Shear, defaults.shear_range},
                                                         {AdjointParameter::Bend, defaults.bend_range},
                                                         {AdjointParameter::Density, {1e-3, 1e2}},
                                                         {AdjointParameter::Damping, defaults.damping_range}};
  for (const auto& text : flags.ranges) {
    std::string name;
    CoefficientRange range;
    require(parse_named_interval(text, name, range.low, range.high), "range",
            "expected COEFFICIENT=LOW:HIGH, got '" + text + "'");
    const auto found =
        std::find_if(ranges.begin(), ranges.end(), [&](const auto& entry) { return name == to_string(entry.first); });
    require(found != ranges.end(), "range",
            "unknown coefficient '" + name + "' (choose from stretch, shear, bend, density, damping)");
    require(std::isfinite(range.low) && std::isfinite(range.high) && range.low > 0.0 && range.low < range.high, "range",
            "'" + text + "' must be 0 < LOW < HIGH");
    found->second = range;
  }
  return ranges;
}

std::vector<AdjointParameter> gradient_coefficients(const std::string& list) {
  std::vector<AdjointParameter> fit;
  for (const auto& name : name_list("fit", list)) {
    AdjointParameter kind = AdjointParameter::Stretch;
    with_flag_names({{"parameter", "fit"}}, [&] { kind = adjoint_parameter_from_name(name); });
    require(is_material_coefficient(kind), "fit",
            "unknown coefficient '" + name + "' (choose from stretch, shear, bend, density, damping)");
    fit.push_back(kind);
  }
  return fit;
}

void run_gradient_fit(FitFlags& flags, int threads) {
  if (flags.coefficients.empty()) flags.coefficients = "stretch,shear,damping";
  const std::vector<AdjointParameter> fit = gradient_coefficients(flags.coefficients);
  const auto ranges = gradient_ranges(flags);
  require(flags.iterations >= 1, "iterations", "must be at least 1");
  with_flag_names({{"fit.frames", "frames"},
                   {"chamfer.samples", "cd-samples"},
                   {"fit.chamfer_stride", "cd-stride"},
                   {"fit.initial_step", "initial-step"},
                   {"fit.final_step", "final-step"}},
                  [&] { flags.params.validate(); });
  const Material start = material_preset(flags.start);
  const auto references = load_references(flags.references);
  std::vector<GradientReference> targets;
  for (const auto& r : references) {
    targets.push_back(gradient_reference(r, start, flags.params));
    const GradientReference& t = targets.back();
    const std::string loss = t.positions ? "position loss on the " + std::to_string(t.targets.size()) +
                                               " after the first (an fnopt rollout: vertex for vertex)"
                                         : "e_CD on " + std::to_string(t.points.size()) + " (every --cd-stride-th)";
    std::printf("reference %s: %dx%d, motion %s, %d steps of %.4g s, %zu frames matched, %s\n", r.path.c_str(),
                r.scene.rows, r.scene.cols, r.scene.motion.c_str(), t.scene.scene.frames - 1, r.scene.dt, t.matched,
                loss.c_str());
  }
  std::printf(
      "fitting %s from %s (%s); bounded L-BFGS in ln(coefficient) on the adjoint gradient, at most %d iterations; %d "
      "thread%s\n",
      flags.coefficients.c_str(), flags.start.c_str(), material_text(start).c_str(), flags.iterations, threads,
      threads == 1 ? "" : "s");
  std::fflush(stdout);
  const GradientFit result =
      fit_by_gradient(targets, start, fit, ranges, flags.iterations, flags.params.initial_step, flags.params.chamfer);
  std::printf("fitted:  %s (%s after %d iterations; loss %s, start %s)\n", material_text(result.material).c_str(),
              to_string(result.status), result.iterations, number_text(result.loss).c_str(),
              number_text(result.start_loss).c_str());
  const FitEvaluation fitted = evaluate_material(references, result.material, flags.params);
  const FitEvaluation before = evaluate_material(references, start, flags.params);
  report_checks(flags, result.material, start);
  write_fit(flags, result.material, fitted, before);
  std::printf(
      "e_CD x 10^3 = %s fitted, %s start material; %d rollouts (%d recorded forward + %d backward passes), and %d "
      "Newton rollouts for e_CD\n",
      number_text(1e3 * fitted.mean_error).c_str(), number_text(1e3 * before.mean_error).c_str(), 2 * result.rollouts,
      result.rollouts, result.rollouts, 2 * static_cast<int>(references.size()));
}

void run_compass_fit(FitFlags& flags, int threads) {
  if (flags.coefficients.empty()) flags.coefficients = "stretch,shear,bend,damping";
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
  report_checks(flags, result.best.material, start);
  write_fit(flags, result.best.material, result.best, result.start);
}

void run_fit(FitFlags& flags) {
  require_writable_file(flags.out, "out");
  const int threads = set_thread_count(flags.threads);
  if (flags.method == "gradient")
    run_gradient_fit(flags, threads);
  else if (flags.method == "compass")
    run_compass_fit(flags, threads);
  else
    throw Error("method", "expected gradient or compass, got '" + flags.method + "'");
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<FitFlags>();
  CLI::App* command = app.add_subcommand(
      "fit-material",
      "fit the material so that fnopt's exact (Newton) rollout reproduces reference rollouts (ARCSim files or "
      "fnopt rollouts), by the rollout's gradient or a compass search on e_CD; writes a material file for "
      "--material");
  command
      ->add_option("--reference", flags->references, "reference rollout(s) to fit to (HDF5); the error is their mean")
      ->required()
      ->check(CLI::ExistingFile);
  command
      ->add_option("--check", flags->checks,
                   "further references to report the fitted material's error on (e.g. other resolutions)")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--method", flags->method,
                   "gradient: bounded L-BFGS in ln(coefficient) on the rollout's adjoint gradient (docs/design.md "
                   "§15), minimising, per reference frame matched by time, the squared distance of every vertex to "
                   "its own (an fnopt rollout) or e_CD (an ARCSim file: --cd-samples, --cd-stride); compass: the "
                   "compass search on e_CD")
      ->capture_default_str();
  command->add_option("--fit", flags->coefficients,
                      "coefficients to fit: stretch, shear, bend, damping, and with --method gradient density "
                      "(default: stretch,shear,damping for gradient, stretch,shear,bend,damping for compass)");
  command->add_option("--iterations", flags->iterations, "gradient: L-BFGS iterations at most")->capture_default_str();
  command->add_option("--range", flags->ranges,
                      "search interval COEFFICIENT=LOW:HIGH (defaults: stretch 1:800 N/m, shear 0.001:1e4 N/m, "
                      "bend 1e-9:0.01 N m, damping 0.001:100 1/s; gradient: density 0.001:100 kg/m^2)");
  command
      ->add_option("--start", flags->start,
                   "material to start from: a preset or a material file (the references' own material is never used)")
      ->capture_default_str();
  command->add_option("--frames", flags->params.frames, "time steps per rollout (0: the reference's whole duration)")
      ->capture_default_str();
  command->add_option("--max-evaluations", flags->params.max_evaluations, "compass: Newton rollouts at most")
      ->capture_default_str();
  command
      ->add_option("--initial-step", flags->params.initial_step,
                   "first step in ln(coefficient): compass, its first poll; gradient, the largest change of a "
                   "coefficient in its first step")
      ->capture_default_str();
  command->add_option("--final-step", flags->params.final_step, "compass: stop when the step is below this")
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
