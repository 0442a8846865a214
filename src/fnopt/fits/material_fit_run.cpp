#include <fnopt/fits/material_fit_run.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fnopt/adjoint/material_gradient.hpp>
#include <fnopt/fits/material_fit_gradient.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

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

std::string thread_text(int threads) { return std::to_string(threads) + " thread" + (threads == 1 ? "" : "s"); }

std::vector<FitReference> load_references(const std::vector<std::string>& paths) {
  std::vector<FitReference> references;
  for (const auto& path : paths) references.push_back(load_fit_reference(path));
  return references;
}

// "COEFFICIENT=LOW:HIGH" as a name and an interval.
CoefficientRange parse_range(const std::string& text, std::string& name) {
  CoefficientRange range;
  require(parse_named_interval(text, name, range.low, range.high), "range",
          "expected COEFFICIENT=LOW:HIGH, got '" + text + "'");
  return range;
}

// The checks: the fitted and the start material's e_CD on further references.
void report_checks(const MaterialFitRun& run, const Material& fitted_material, const Material& start) {
  for (const auto& reference : load_references(run.checks)) {
    const auto fitted = evaluate_material({reference}, fitted_material, run.params);
    const auto before = evaluate_material({reference}, start, run.params);
    std::printf("check %s (%dx%d, %s): e_CD x 10^3 = %s fitted, %s start material\n", reference.path.c_str(),
                reference.scene.rows, reference.scene.cols, reference.scene.motion.c_str(),
                number_text(1e3 * fitted.mean_error).c_str(), number_text(1e3 * before.mean_error).c_str());
  }
}

// The material file, its comment saying how it was fitted.
void write_fit(const MaterialFitRun& run, const Material& material, const FitEvaluation& fitted,
               const FitEvaluation& start) {
  std::string comment = "fitted by fnopt fit-material --method " + run.method + " (" + run.coefficients + ") to";
  for (const auto& path : run.references) comment += "\n  " + path;
  comment += "\ne_CD x 10^3 = " + number_text(1e3 * fitted.mean_error) +
             " (start material: " + number_text(1e3 * start.mean_error) + ")";
  write_material_file(run.out, material, comment);
  std::printf("wrote %s (use it with --material %s)\n", run.out.c_str(), run.out.c_str());
}

// The gradient method's parameters from the run's coefficients, ranges and budget.
GradientMaterialFitParams gradient_params(const MaterialFitRun& run) {
  GradientMaterialFitParams params;
  params.fit.clear();
  for (const auto& name : name_list("fit", run.coefficients)) {
    AdjointParameter kind = AdjointParameter::Stretch;
    with_flag_names({{"parameter", "fit"}}, [&] { kind = adjoint_parameter_from_name(name); });
    require(is_material_coefficient(kind), "fit",
            "unknown coefficient '" + name + "' (choose from stretch, shear, bend, density, damping)");
    params.fit.push_back(kind);
  }
  for (const auto& text : run.ranges) {
    std::string name;
    const CoefficientRange range = parse_range(text, name);
    const auto found = std::find_if(params.ranges.begin(), params.ranges.end(),
                                    [&](const auto& entry) { return name == to_string(entry.first); });
    require(found != params.ranges.end(), "range",
            "unknown coefficient '" + name + "' (choose from stretch, shear, bend, density, damping)");
    require(std::isfinite(range.low) && std::isfinite(range.high) && range.low > 0.0 && range.low < range.high, "range",
            "'" + text + "' must be 0 < LOW < HIGH");
    found->second = range;
  }
  if (!run.horizons.empty()) params.horizons.clear();  // "none", or the stages that follow
  if (!run.horizons.empty() && run.horizons != "none") {
    for (const auto& item : split(run.horizons, ',')) {
      double fraction = 0.0;
      require(parse_double(trim(item), fraction), "horizons",
              "expected none or fractions of the steps such as 0.33,0.67, got '" + run.horizons + "'");
      params.horizons.push_back(fraction);
    }
  }
  params.optimizer.max_evaluations = run.params.max_evaluations;
  params.optimizer.first_step = run.params.initial_step;
  params.chamfer = run.params.chamfer;
  return params;
}

void print_gradient_reference(const FitReference& r, const GradientFitTarget& t) {
  const std::string loss = !t.positions.empty() ? "position loss on the " + std::to_string(t.positions.size()) +
                                                      " after the first (an fnopt rollout: vertex for vertex)"
                                                : "e_CD on " + std::to_string(t.points.size()) +
                                                      " (every --cd-stride-th)";
  std::printf("reference %s: %dx%d, motion %s, %d steps of %.4g s, %zu frames matched, %s\n", r.path.c_str(),
              r.scene.rows, r.scene.cols, r.scene.motion.c_str(), t.scene.scene.frames - 1, r.scene.dt, t.matched,
              loss.c_str());
}

// "stretch/rho" for a stiffness, the coefficient's name otherwise, and the unit of either.
std::pair<std::string, std::string> identifiable_name(AdjointParameter kind) {
  switch (kind) {
    case AdjointParameter::Stretch:
      return {"stretch/rho", "m^2/s^2"};
    case AdjointParameter::Shear:
      return {"shear/rho", "m^2/s^2"};
    case AdjointParameter::Bend:
      return {"bend/rho", "m^4/s^2"};
    default:
      return {to_string(kind), "1/s"};
  }
}

const char* stop_text(BoundedGaussNewtonStatus status) {
  switch (status) {
    case BoundedGaussNewtonStatus::Stationary:
      return "stationary: the Gauss-Newton step changes no coefficient by more than 1e-6";
    case BoundedGaussNewtonStatus::Settled:
      return "not stationary: the Gauss-Newton model promises little more decrease";
    case BoundedGaussNewtonStatus::NoDecrease:
      return "not stationary: no step lowers the loss any more (it is rough at the solver's precision there)";
    case BoundedGaussNewtonStatus::EvaluationBudget:
      return "not stationary: stopped at --max-evaluations";
    case BoundedGaussNewtonStatus::NonFinite:
      return "not stationary: the start material's rollout diverges";
  }
  return "";
}

// The fitted values in the coordinates the positions determine, each with its uncertainty.
void print_identifiable(const GradientMaterialFitParams& params, const GradientMaterialFitResult& result) {
  const double rho = result.material.density;
  for (std::size_t i = 0; i < params.fit.size(); ++i) {
    const auto [name, unit] = identifiable_name(params.fit[i]);
    const double k = material_coefficient(result.material, params.fit[i]);
    const bool stiffness = params.fit[i] != AdjointParameter::Damping;
    std::printf("  %-12s = %-12.6g %-8s +- %.2g %%", name.c_str(), stiffness ? k / rho : k, unit.c_str(),
                100.0 * result.uncertainty[i]);
    if (stiffness) std::printf("   (%s %.6g at density %.4g kg/m^2)", to_string(params.fit[i]), k, rho);
    if (result.at_bound[i]) std::printf("   at an end of its --range");
    std::printf("\n");
  }
}

// ", first 33 % of the steps" for a stage before the whole horizon.
std::string horizon_text(double horizon) {
  if (horizon >= 1.0) return "";
  char text[64];
  std::snprintf(text, sizeof text, " (the first %.0f %% of the steps)", 100.0 * horizon);
  return text;
}

// ", in stages: the first 33 % of the steps, then all (--horizons)" where there are stages.
std::string stages_text(const std::vector<double>& horizons) {
  if (horizons.empty()) return "";
  std::string text = ", in stages: the first";
  for (std::size_t i = 0; i < horizons.size(); ++i)
    text += (i ? ", " : " ") + std::to_string(static_cast<int>(std::lround(100.0 * horizons[i]))) + " %";
  return text + " of the steps, then all (--horizons)";
}

void run_gradient_fit(MaterialFitRun& run, const Material& start) {
  const GradientMaterialFitParams params = gradient_params(run);
  params.validate();
  with_flag_names({{"fit.frames", "frames"},
                   {"chamfer.samples", "cd-samples"},
                   {"fit.chamfer_stride", "cd-stride"},
                   {"fit.initial_step", "initial-step"},
                   {"fit.final_step", "final-step"},
                   {"fit.max_evaluations", "max-evaluations"}},
                  [&] { run.params.validate(); });
  const auto references = load_references(run.references);
  std::vector<GradientFitTarget> targets;
  for (const auto& r : references) {
    targets.push_back(gradient_fit_target(r, start, run.params));
    print_gradient_reference(r, targets.back());
  }
  std::printf(
      "fitting %s from %s (%s): positions determine the stiffnesses only relative to the density, held at %.4g "
      "kg/m^2 (%s); Levenberg-Marquardt in ln(coefficient) on the Gauss-Newton model of the rollout's tangents%s, "
      "at most %d evaluations; %s\n",
      run.coefficients.c_str(), run.start.c_str(), material_text(start).c_str(), start.density,
      run.mass > 0.0 ? "--mass" : "the start's; --mass sets it", stages_text(params.horizons).c_str(),
      params.optimizer.max_evaluations, thread_text(run.threads).c_str());
  std::fflush(stdout);
  const GradientMaterialFitResult result =
      fit_material_by_gradient(targets, start, params,
                               [](int evaluation, double horizon, const Material& material, double loss) {
                                 std::printf("  %3d  %s  ->  loss %s%s\n", evaluation, material_text(material).c_str(),
                                             number_text(loss).c_str(), horizon_text(horizon).c_str());
                                 std::fflush(stdout);
                               });
  std::printf("fitted (%s; %d steps, loss %s, start %s), +- one standard deviation from the Gauss-Newton model:\n",
              stop_text(result.status), result.iterations, number_text(result.loss).c_str(),
              number_text(result.start_loss).c_str());
  print_identifiable(params, result);
  const FitEvaluation fitted = evaluate_material(references, result.material, run.params);
  const FitEvaluation before = evaluate_material(references, start, run.params);
  report_checks(run, result.material, start);
  write_fit(run, result.material, fitted, before);
  std::printf(
      "e_CD x 10^3 = %s fitted, %s start material; %d rollouts (%d recorded forward + %d tangent passes), and %d "
      "Newton rollouts for e_CD\n",
      number_text(1e3 * fitted.mean_error).c_str(), number_text(1e3 * before.mean_error).c_str(), 2 * result.rollouts,
      result.rollouts, result.rollouts, 2 * static_cast<int>(references.size()));
}

// The compass's coefficients and intervals from the run, validated with the flags' names.
void set_compass_params(MaterialFitRun& run) {
  run.params.coefficients.clear();
  for (auto name : split(run.coefficients, ','))
    run.params.coefficients.push_back(material_coefficient(std::string(trim(name))));
  for (const auto& text : run.ranges) {
    std::string name;
    const CoefficientRange range = parse_range(text, name);
    run.params.range(material_coefficient(name)) = range;
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
                  [&] { run.params.validate(); });
}

void run_compass_fit(MaterialFitRun& run, const Material& start) {
  set_compass_params(run);
  const auto references = load_references(run.references);
  for (const auto& r : references)
    std::printf("reference %s: %dx%d, motion %s, %d steps of %.4g s\n", r.path.c_str(), r.scene.rows, r.scene.cols,
                r.scene.motion.c_str(), run.params.frames > 0 ? run.params.frames : r.scene.frames, r.scene.dt);
  std::printf(
      "fitting %s from %s (%s); compass search in ln(coefficient), step %.3g down to %.3g, at most %d "
      "Newton rollouts per reference; %s\n",
      run.coefficients.c_str(), run.start.c_str(), material_text(start).c_str(), run.params.initial_step,
      run.params.final_step, run.params.max_evaluations, thread_text(run.threads).c_str());

  ProgressBar bar("fit", run.params.max_evaluations);
  const MaterialFitResult result =
      fit_material(references, start, run.params, [&](int k, const FitEvaluation& e, const FitEvaluation& best) {
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
  report_checks(run, result.best.material, start);
  write_fit(run, result.best.material, result.best, result.start);
}

// The start material: the preset or file, its density set by --mass where given.
Material start_material(const MaterialFitRun& run) {
  Material start = material_preset(run.start);
  require(std::isfinite(run.mass) && run.mass >= 0.0, "mass", "must be at least 0 (0: the start's density)");
  if (run.mass > 0.0) {
    const Scene& scene = load_fit_reference(run.references.front()).scene;
    const Grid grid = Grid::make(scene.rows, scene.cols, scene.size);
    start.density = run.mass / ((grid.rows - 1) * (grid.cols - 1) * grid.spacing * grid.spacing);
  }
  return start;
}

}  // namespace

void run_material_fit(MaterialFitRun run) {
  if (run.coefficients.empty()) run.coefficients = "stretch,shear,bend,damping";
  const Material start = start_material(run);
  if (run.method == "gradient")
    run_gradient_fit(run, start);
  else if (run.method == "compass")
    run_compass_fit(run, start);
  else
    throw Error("method", "expected gradient or compass, got '" + run.method + "'");
}

}  // namespace fnopt
