#include <fnopt/adjoint/gradient_material_fit.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

void GradientMaterialFitParams::validate() const {
  require(!fit.empty(), "fit", "name at least one material coefficient");
  for (std::size_t i = 0; i < fit.size(); ++i) {
    require(is_material_coefficient(fit[i]), "fit",
            std::string(to_string(fit[i])) + " is not a material coefficient (stretch, shear, bend, density, damping)");
    require(std::find(fit.begin(), fit.begin() + i, fit[i]) == fit.begin() + i, "fit",
            std::string(to_string(fit[i])) + " is named twice");
  }
  require(std::isfinite(range) && range > 1.0, "range", "must be above 1");
  optimizer.validate();
  record.validate();
}

GradientMaterialFitResult fit_material_by_gradient(const ResolvedScene& scene,
                                                   const std::vector<FramePositions>& observed,
                                                   const GradientMaterialFitParams& params,
                                                   const RolloutInputs& inputs) {
  params.validate();
  const Eigen::Index n = static_cast<Eigen::Index>(params.fit.size());
  ResolvedScene current = scene;
  VecX start(n), lower(n), upper(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double k0 = material_coefficient(current.scene.material, params.fit[i]);
    require(k0 > 0.0, "fit", std::string(to_string(params.fit[i])) + " must start positive to be fitted in log");
    start[i] = std::log(k0);
    lower[i] = start[i] - std::log(params.range);
    upper[i] = start[i] + std::log(params.range);
  }

  GradientMaterialFitResult result;
  const auto set_material = [&](const VecX& log_k) {
    for (Eigen::Index i = 0; i < n; ++i) material_coefficient(current.scene.material, params.fit[i]) = std::exp(log_k[i]);
  };
  const BoundedObjective loss = [&](const VecX& log_k, VecX& gradient) {
    set_material(log_k);
    const RecordedRollout rollout = record_rollout(current, params.record, inputs);
    require(!rollout.diverged, "rollout", "the rollout at a trial material " + rollout.divergence);
    const RolloutLoss value = position_loss(rollout, observed);
    const RolloutGradient adjoint = backpropagate(rollout, value.gradient);
    ++result.rollouts;
    gradient.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) gradient[i] = adjoint.log_material.coefficient(params.fit[i]);
    return value.value;
  };
  const BoundedLbfgsResult fit = minimize_in_box(loss, start, lower, upper, params.optimizer);
  set_material(fit.x);
  result.material = current.scene.material;
  result.loss = fit.value;
  result.status = fit.status;
  result.iterations = fit.iterations;
  return result;
}

}  // namespace fnopt
