#include <fnopt/fits/material_fit.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <fnopt/fits/compass_search.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double rollout_error(const FitReference& reference, const Material& material, const MaterialFitParams& params) {
  Scene scene = reference.scene;
  scene.material = material;
  if (params.frames > 0) scene.frames = params.frames;
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = {NewtonOptimizer::reference_solve_options().max_iterations, params.newton_tolerance};
  const RolloutResult rollout = run_rollout(resolve(scene), newton, options);
  if (rollout.diverged) return std::numeric_limits<double>::infinity();
  TrajectoryComparisonOptions comparison;
  comparison.chamfer = params.chamfer;
  comparison.chamfer_stride = params.chamfer_stride;
  const TrajectoryComparison c = compare_trajectories(reference.frames, frames_of(rollout), 0.0, comparison);
  return std::isfinite(c.chamfer) ? c.chamfer : std::numeric_limits<double>::infinity();
}

}  // namespace

MaterialCoefficient material_coefficient(const std::string& name) {
  if (name == "stretch") return MaterialCoefficient::Stretch;
  if (name == "shear") return MaterialCoefficient::Shear;
  if (name == "bend") return MaterialCoefficient::Bend;
  if (name == "damping") return MaterialCoefficient::Damping;
  throw Error("fit", "unknown coefficient '" + name + "' (choose from stretch, shear, bend, damping)");
}

std::string coefficient_name(MaterialCoefficient coefficient) {
  switch (coefficient) {
    case MaterialCoefficient::Stretch:
      return "stretch";
    case MaterialCoefficient::Shear:
      return "shear";
    case MaterialCoefficient::Bend:
      return "bend";
    case MaterialCoefficient::Damping:
      return "damping";
  }
  return "";
}

double coefficient_of(const Material& material, MaterialCoefficient coefficient) {
  return coefficient_of(const_cast<Material&>(material), coefficient);
}

double& coefficient_of(Material& material, MaterialCoefficient coefficient) {
  switch (coefficient) {
    case MaterialCoefficient::Stretch:
      return material.stretch;
    case MaterialCoefficient::Shear:
      return material.shear;
    case MaterialCoefficient::Bend:
      return material.bend;
    case MaterialCoefficient::Damping:
      return material.damping;
  }
  return material.stretch;
}

const CoefficientRange& MaterialFitParams::range(MaterialCoefficient coefficient) const {
  switch (coefficient) {
    case MaterialCoefficient::Stretch:
      return stretch_range;
    case MaterialCoefficient::Shear:
      return shear_range;
    case MaterialCoefficient::Bend:
      return bend_range;
    case MaterialCoefficient::Damping:
      return damping_range;
  }
  return stretch_range;
}

CoefficientRange& MaterialFitParams::range(MaterialCoefficient coefficient) {
  return const_cast<CoefficientRange&>(static_cast<const MaterialFitParams&>(*this).range(coefficient));
}

void MaterialFitParams::validate() const {
  require(!coefficients.empty(), "fit.coefficients", "name at least one coefficient to fit");
  for (std::size_t i = 0; i < coefficients.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      require(coefficients[i] != coefficients[j], "fit.coefficients",
              "'" + coefficient_name(coefficients[i]) + "' is named twice");
  for (auto c : {MaterialCoefficient::Stretch, MaterialCoefficient::Shear, MaterialCoefficient::Bend,
                 MaterialCoefficient::Damping}) {
    const auto& r = range(c);
    require(std::isfinite(r.low) && std::isfinite(r.high) && r.low > 0.0 && r.low < r.high,
            "fit." + coefficient_name(c) + "_range", "must be 0 < low < high");
  }
  require(std::isfinite(initial_step) && initial_step > 0.0, "fit.initial_step", "must be positive");
  require(std::isfinite(final_step) && final_step > 0.0 && final_step <= initial_step, "fit.final_step",
          "must be positive and at most the initial step");
  require(max_evaluations >= 1, "fit.max_evaluations", "must be at least 1");
  require(frames >= 0, "fit.frames", "must be non-negative (0: the reference's duration)");
  require(std::isfinite(newton_tolerance) && newton_tolerance > 0.0 && newton_tolerance < 1.0, "fit.newton_tolerance",
          "must be in (0, 1)");
  require(chamfer_stride >= 1, "fit.chamfer_stride", "must be at least 1");
  chamfer.validate();
}

FitReference load_fit_reference(const std::string& path, const Scene& base) {
  FitReference reference;
  reference.path = path;
  reference.frames = read_trajectory_frames(path);
  const Hdf5File file(path, Hdf5File::Mode::Read);
  if (file.has_attribute("scene")) {
    reference.scene = read_rollout_scene(path);
  } else {
    require(file.has_attribute("motion"), path,
            "neither an fnopt rollout (no 'scene' attribute) nor an ARCSim reference (no 'motion' attribute)");
    reference.scene = base;
    reference.scene.rows = reference.frames.rows;
    reference.scene.cols = reference.frames.cols;
    reference.scene.motion = file.string_attribute("motion");
    reference.scene.trajectory.clear();
    reference.scene.handles = "corner";
    reference.scene.handle_vertices.clear();
    reference.scene.frames = static_cast<int>(
        std::lround((reference.frames.times.back() - reference.frames.times.front()) / reference.scene.dt));
  }
  require(reference.scene.rows == reference.frames.rows && reference.scene.cols == reference.frames.cols, path,
          "its stored scene's grid does not match its positions");
  require(reference.scene.frames >= 1, path, "holds no time steps to fit to");
  reference.scene.validate();
  return reference;
}

FitEvaluation evaluate_material(const std::vector<FitReference>& references, const Material& material,
                                const MaterialFitParams& params) {
  require(!references.empty(), "fit", "no reference to fit to");
  material.validate();
  FitEvaluation evaluation;
  evaluation.material = material;
  for (const auto& reference : references) evaluation.errors.push_back(rollout_error(reference, material, params));
  double sum = 0.0;
  for (double e : evaluation.errors) sum += e;
  evaluation.mean_error = sum / evaluation.errors.size();
  return evaluation;
}

MaterialFitResult fit_material(const std::vector<FitReference>& references, const Material& start,
                               const MaterialFitParams& params, const FitCallback& on_evaluation) {
  params.validate();
  const auto& coefficients = params.coefficients;
  const Eigen::Index n = static_cast<Eigen::Index>(coefficients.size());

  // The search point: ln of each chosen coefficient, clamped to its range.
  VecX point(n), lower(n), upper(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double value = coefficient_of(start, coefficients[i]);
    if (!(value > 0.0)) value = coefficient_of(Material{}, coefficients[i]);
    if (!(value > 0.0)) value = 1.0;
    const auto& range = params.range(coefficients[i]);
    lower[i] = std::log(range.low);
    upper[i] = std::log(range.high);
    point[i] = std::log(std::clamp(value, range.low, range.high));
  }
  auto material_at = [&](const VecX& p) {
    Material m = start;
    for (Eigen::Index i = 0; i < n; ++i) coefficient_of(m, coefficients[i]) = std::exp(p[i]);
    return m;
  };

  MaterialFitResult result;
  const auto error = [&](const VecX& p) {
    const FitEvaluation e = evaluate_material(references, material_at(p), params);
    ++result.evaluations;
    if (result.evaluations == 1) result.start = e;
    if (result.evaluations == 1 || e.mean_error < result.best.mean_error) result.best = e;
    if (on_evaluation) on_evaluation(result.evaluations, e, result.best);
    return e.mean_error;
  };
  const CompassSearchResult search =
      minimize_by_compass(error, point, lower, upper, {params.initial_step, params.final_step, params.max_evaluations});
  result.final_step = search.final_step;
  result.converged = search.converged;
  return result;
}

void write_material_file(const std::string& path, const Material& material, const std::string& comment) {
  std::ostringstream text;
  text.precision(17);
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) text << "# " << line << "\n";
  text << "stretch = " << material.stretch << "\n"
       << "shear = " << material.shear << "\n"
       << "bend = " << material.bend << "\n"
       << "density = " << material.density << "\n"
       << "damping = " << material.damping << "\n"
       << "repulsion_stiffness = " << material.repulsion_stiffness << "\n"
       << "repulsion_range = " << material.repulsion_range << "\n";
  write_text_atomically(path, text.str());
}

}  // namespace fnopt
