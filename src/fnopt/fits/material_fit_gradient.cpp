#include <fnopt/fits/material_fit_gradient.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fnopt/adjoint/material_gradient.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/metrics/frame_matching.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

GradientFitTarget gradient_fit_target(const FitReference& reference, const Material& start,
                                      const MaterialFitParams& params) {
  GradientFitTarget target;
  Scene scene = reference.scene;
  scene.material = start;
  if (params.frames > 0) scene.frames = params.frames;
  scene.frames += 1;  // the recorded rollout counts the initial frame
  target.scene = resolve(scene);
  const bool positions = Hdf5File(reference.path, Hdf5File::Mode::Read).has_attribute("scene");
  std::vector<double> times(scene.frames);
  for (int f = 0; f < scene.frames; ++f) times[f] = reference.frames.times.front() + f * scene.dt;
  Grid reference_grid;
  reference_grid.rows = reference.frames.rows;
  reference_grid.cols = reference.frames.cols;
  const Triangles triangles = reference_grid.triangles();
  const std::vector<FrameMatch> matches = match_frames(reference.frames.times, times);
  target.matched = matches.size();
  for (std::size_t k = 0; k < matches.size(); ++k) {
    const FrameMatch& match = matches[k];
    const Eigen::VectorXf& x = reference.frames.positions[match.reference];
    if (positions && match.rollout > 0) target.positions.push_back({match.rollout, x.cast<double>()});
    if (!positions && k % params.chamfer_stride == 0)
      target.points.push_back({match.rollout, sample_mesh_surface(x.cast<double>(), triangles, params.chamfer.samples,
                                                                  params.chamfer.seed)});
  }
  require(!target.positions.empty() || !target.points.empty(), reference.path,
          "no frame after the first matches the rollout's times");
  return target;
}

std::map<AdjointParameter, CoefficientRange> GradientMaterialFitParams::default_ranges() {
  const MaterialFitParams compass;
  return {{AdjointParameter::Stretch, compass.stretch_range},
          {AdjointParameter::Shear, compass.shear_range},
          {AdjointParameter::Bend, compass.bend_range},
          {AdjointParameter::Density, {1e-3, 1e2}},
          {AdjointParameter::Damping, compass.damping_range}};
}

BoundedLbfgsParams GradientMaterialFitParams::default_optimizer() {
  BoundedLbfgsParams params;
  params.max_iterations = 30;
  params.max_backtracks = 10;
  params.relative_decrease = 1e-4;
  params.first_step = MaterialFitParams{}.initial_step;
  return params;
}

void GradientMaterialFitParams::validate() const {
  require(!fit.empty(), "fit", "name at least one material coefficient");
  for (std::size_t i = 0; i < fit.size(); ++i) {
    require(is_material_coefficient(fit[i]), "fit",
            std::string(to_string(fit[i])) + " is not a material coefficient (stretch, shear, bend, density, damping)");
    require(std::find(fit.begin(), fit.begin() + i, fit[i]) == fit.begin() + i, "fit",
            std::string(to_string(fit[i])) + " is named twice");
    const auto range = ranges.find(fit[i]);
    require(range != ranges.end(), "range", std::string("no interval for ") + to_string(fit[i]));
    require(std::isfinite(range->second.low) && std::isfinite(range->second.high) && range->second.low > 0.0 &&
                range->second.low < range->second.high,
            "range", std::string(to_string(fit[i])) + " must be 0 < LOW < HIGH");
  }
  optimizer.validate();
  record.validate();
}

namespace {

// The mean loss over the targets at `material` and its gradient in ln k of the fitted
// coefficients; +inf (and an unset gradient) once a rollout diverges.
double mean_loss(const std::vector<GradientFitTarget>& targets, const Material& material,
                 const GradientMaterialFitParams& params, VecX& gradient, int& rollouts) {
  const Eigen::Index n = static_cast<Eigen::Index>(params.fit.size());
  gradient = VecX::Zero(n);
  double value = 0.0;
  for (const GradientFitTarget& target : targets) {
    ResolvedScene scene = target.scene;
    scene.scene.material = material;
    const RecordedRollout rollout = record_rollout(scene, params.record);
    ++rollouts;
    if (rollout.diverged) return std::numeric_limits<double>::infinity();
    const RolloutLoss loss = target.points.empty() ? position_loss(rollout, target.positions)
                                                   : surface_chamfer_loss(rollout, target.points, params.chamfer);
    const RolloutGradient adjoint = backpropagate(rollout, loss.gradient);
    value += loss.value / targets.size();
    for (Eigen::Index i = 0; i < n; ++i)
      gradient[i] += adjoint.log_material.coefficient(params.fit[i]) / targets.size();
  }
  return value;
}

}  // namespace

GradientMaterialFitResult fit_material_by_gradient(const std::vector<GradientFitTarget>& targets,
                                                   const Material& start, const GradientMaterialFitParams& params,
                                                   const GradientFitCallback& on_evaluation) {
  params.validate();
  const Eigen::Index n = static_cast<Eigen::Index>(params.fit.size());
  VecX x0(n), lower(n), upper(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const CoefficientRange& range = params.ranges.at(params.fit[i]);
    lower[i] = std::log(range.low);
    upper[i] = std::log(range.high);
    x0[i] = std::clamp(std::log(material_coefficient(start, params.fit[i])), lower[i], upper[i]);
  }
  const auto material_at = [&](const VecX& x) {
    Material m = start;
    for (Eigen::Index i = 0; i < n; ++i) material_coefficient(m, params.fit[i]) = std::exp(x[i]);
    return m;
  };
  GradientMaterialFitResult result;
  int evaluations = 0;
  const BoundedObjective objective = [&](const VecX& x, VecX& gradient) {
    const Material material = material_at(x);
    const double value = mean_loss(targets, material, params, gradient, result.rollouts);
    if (++evaluations == 1) result.start_loss = value;
    if (on_evaluation) on_evaluation(evaluations, material, value);
    return value;
  };
  const BoundedLbfgsResult fit = minimize_in_box(objective, x0, lower, upper, params.optimizer);
  result.material = material_at(fit.x);
  result.loss = fit.value;
  result.status = fit.status;
  result.iterations = fit.iterations;
  return result;
}

}  // namespace fnopt
