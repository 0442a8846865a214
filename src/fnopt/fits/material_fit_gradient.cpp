#include <fnopt/fits/material_fit_gradient.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include <fnopt/adjoint/material_gradient.hpp>
#include <fnopt/adjoint/step_linearization.hpp>
#include <fnopt/adjoint/step_states.hpp>
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

BoundedGaussNewtonParams GradientMaterialFitParams::default_optimizer() {
  BoundedGaussNewtonParams params;
  params.max_evaluations = 30;
  params.step_tolerance = 1e-6;
  params.first_step = MaterialFitParams{}.initial_step;
  params.max_step = 1.0;
  return params;
}

void GradientMaterialFitParams::validate() const {
  require(!fit.empty(), "fit", "name at least one material coefficient");
  for (std::size_t i = 0; i < fit.size(); ++i) {
    require(is_material_coefficient(fit[i]), "fit",
            std::string(to_string(fit[i])) + " is not a material coefficient (stretch, shear, bend, density, damping)");
    require(std::find(fit.begin(), fit.begin() + i, fit[i]) == fit.begin() + i, "fit",
            std::string(to_string(fit[i])) + " is named twice");
    require(fit[i] != AdjointParameter::Density, "fit",
            "density is not determined by positions (scaling it and the stiffnesses together changes no rollout): "
            "fit the others relative to it, and give the cloth's mass to set it");
    const auto range = ranges.find(fit[i]);
    require(range != ranges.end(), "range", std::string("no interval for ") + to_string(fit[i]));
    require(std::isfinite(range->second.low) && std::isfinite(range->second.high) && range->second.low > 0.0 &&
                range->second.low < range->second.high,
            "range", std::string(to_string(fit[i])) + " must be 0 < LOW < HIGH");
  }
  for (std::size_t i = 0; i < horizons.size(); ++i)
    require(std::isfinite(horizons[i]) && horizons[i] > 0.0 && horizons[i] < 1.0 &&
                (i == 0 || horizons[i] > horizons[i - 1]),
            "horizons", "expected fractions of the steps ascending in (0, 1)");
  optimizer.validate();
  record.validate();
}

namespace {

// One target's loss at `material`, its gradient in ln k of the fitted coefficients and its
// Gauss-Newton model, by one tangent pass per coefficient (the header's); +inf where the rollout
// diverges or a step's Hessian is singular. `residuals` gains the loss's residual components.
double target_loss(const GradientFitTarget& target, const Material& material, const GradientMaterialFitParams& params,
                   VecX& gradient, Eigen::MatrixXd& model, long& residuals) {
  const Eigen::Index n = static_cast<Eigen::Index>(params.fit.size());
  ResolvedScene scene = target.scene;
  scene.scene.material = material;
  const RecordedRollout rollout = record_rollout(scene, params.record);
  if (rollout.diverged) return std::numeric_limits<double>::infinity();
  const RolloutLoss loss = target.points.empty() ? position_loss(rollout, target.positions)
                                                 : surface_chamfer_loss(rollout, target.points, params.chamfer);
  std::vector<int> term_of_frame(rollout.frame_count(), -1);
  int last = 0;
  for (std::size_t t = 0; t < loss.gradient.size(); ++t) {
    term_of_frame[loss.gradient[t].frame] = static_cast<int>(t);
    last = std::max(last, loss.gradient[t].frame);
  }
  for (const FramePositions& frame : target.positions) residuals += frame.positions.size();
  for (const FramePoints& frame : target.points)
    residuals += 3 * static_cast<long>(frame.points.size() + params.chamfer.samples);
  StepLinearization step(rollout.scene);
  StepStates states(rollout);
  const Eigen::Index dofs = rollout.positions.front().size();
  Eigen::MatrixXd dx = Eigen::MatrixXd::Zero(dofs, n), dv = dx;
  VecX column_x, column_v, source;
  for (int s = 0; s < last; ++s) {
    states.load(s);
    step.set_released(rollout.steps[s].released);
    if (step.linearize(states.x(), states.v(), states.a(), s * scene.scene.dt) == StepStationarity::Singular)
      return std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < n; ++j) {
      step.log_material_derivative(params.fit[j], source);
      column_x = dx.col(j), column_v = dv.col(j);
      step.advance_tangent(column_x, column_v, &source);
      dx.col(j) = column_x, dv.col(j) = column_v;
    }
    const int term = term_of_frame[s + 1];
    if (term < 0) continue;
    gradient += dx.transpose() * loss.gradient[term].gradient;
    model += dx.transpose() * loss.gauss_newton_weights[term].asDiagonal() * dx;
  }
  return loss.value;
}

// The mean over the targets of target_loss.
double mean_loss(const std::vector<GradientFitTarget>& targets, const Material& material,
                 const GradientMaterialFitParams& params, VecX& gradient, Eigen::MatrixXd& model, int& rollouts,
                 long& residuals) {
  const Eigen::Index n = static_cast<Eigen::Index>(params.fit.size());
  gradient = VecX::Zero(n);
  model = Eigen::MatrixXd::Zero(n, n);
  residuals = 0;
  double value = 0.0;
  for (const GradientFitTarget& target : targets) {
    ++rollouts;
    value += target_loss(target, material, params, gradient, model, residuals);
    if (!std::isfinite(value)) return value;
  }
  const double count = static_cast<double>(targets.size());
  gradient /= count;
  model /= count;
  return value / count;
}

// sqrt(s^2 (J^T J)^-1_ii) in ln k (GradientMaterialFitResult::uncertainty): for the mean loss L and
// its model G = 2 J^T J / T over T targets, s^2 (J^T J)^-1 = 2 L G^-1 / (N - p). A coefficient the
// positions do not see (a singular G) is infinitely uncertain.
std::vector<double> uncertainties(double loss, const Eigen::MatrixXd& model, long residuals) {
  const Eigen::Index p = model.rows();
  const Eigen::LDLT<Eigen::MatrixXd> factor(model);
  Eigen::MatrixXd inverse = factor.solve(Eigen::MatrixXd::Identity(p, p));
  const double variance = 2.0 * loss / static_cast<double>(std::max<long>(1, residuals - p));
  std::vector<double> out(p, std::numeric_limits<double>::infinity());
  if (factor.info() != Eigen::Success || !factor.isPositive() || !inverse.allFinite()) return out;
  for (Eigen::Index i = 0; i < p; ++i) out[i] = std::sqrt(std::max(0.0, variance * inverse(i, i)));
  return out;
}

// The target over the first round(fraction x steps) steps (at least one): its scene's frames and the
// loss's frames within them. Throws Error("horizons", ...) where no loss frame is left.
GradientFitTarget truncated(const GradientFitTarget& target, double fraction) {
  GradientFitTarget out = target;
  const int steps = std::max(1, static_cast<int>(std::lround(fraction * (target.scene.scene.frames - 1))));
  out.scene.scene.frames = steps + 1;
  const auto beyond = [&](const auto& frame) { return frame.frame > steps; };
  out.positions.erase(std::remove_if(out.positions.begin(), out.positions.end(), beyond), out.positions.end());
  out.points.erase(std::remove_if(out.points.begin(), out.points.end(), beyond), out.points.end());
  require(!out.positions.empty() || !out.points.empty(), "horizons",
          "a stage of " + std::to_string(steps) + " steps has no reference frame in it (choose a larger fraction)");
  return out;
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
  long residuals = 0;
  std::vector<double> stages = params.horizons;
  stages.push_back(1.0);
  BoundedGaussNewtonResult fit;
  VecX x = x0;
  for (double horizon : stages) {
    std::vector<GradientFitTarget> stage_targets;
    for (const GradientFitTarget& target : targets)
      stage_targets.push_back(horizon < 1.0 ? truncated(target, horizon) : target);
    const int stage_start = evaluations;
    const GaussNewtonObjective objective = [&](const VecX& at, VecX& gradient, Eigen::MatrixXd& model) {
      const Material material = material_at(at);
      const double value = mean_loss(stage_targets, material, params, gradient, model, result.rollouts, residuals);
      if (++evaluations == stage_start + 1) result.start_loss = value;
      if (on_evaluation) on_evaluation(evaluations, horizon, material, value);
      return value;
    };
    BoundedGaussNewtonParams optimizer = params.optimizer;
    optimizer.max_evaluations = std::max(1, params.optimizer.max_evaluations - evaluations);
    if (horizon < 1.0) {
      optimizer.step_tolerance = std::max(optimizer.step_tolerance, GradientMaterialFitParams::kStageStepTolerance);
      optimizer.decrease_tolerance = GradientMaterialFitParams::kStageDecreaseTolerance;
    }
    fit = minimize_by_gauss_newton(objective, x, lower, upper, optimizer);
    x = fit.x;
    result.iterations += fit.iterations;
    if (fit.status == BoundedGaussNewtonStatus::NonFinite) break;
  }
  result.material = material_at(fit.x);
  result.loss = fit.value;
  result.status = fit.status;
  result.uncertainty = uncertainties(fit.value, fit.model, residuals);
  for (Eigen::Index i = 0; i < n; ++i) result.at_bound.push_back(fit.x[i] <= lower[i] || fit.x[i] >= upper[i]);
  return result;
}

}  // namespace fnopt
