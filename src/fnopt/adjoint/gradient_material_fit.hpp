#pragma once
// A material fitted by its gradient (docs/design.md §15): the coefficients that make the scene's
// rollout of exact steps match observed positions, by projected L-BFGS (bounded_lbfgs.hpp) in
// the logarithms of the coefficients, each within a box around its start, on
//   L(theta) = sum over the observed frames of sum_i |x_f,i(theta) - observed_f,i|^2
// and its adjoint gradient dL/dlog k (rollout_adjoint.hpp), one forward and one backward pass per
// evaluation. The rollout's dynamics depend on the stiffnesses and the damping relative to the
// density (gravity fixed), so density and all three stiffnesses together are not identifiable:
// fit a subset (the default: stretch, shear and damping, as `fnopt fit-material`).
#include <vector>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/adjoint/bounded_lbfgs.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>

namespace fnopt {

struct GradientMaterialFitParams {
  // Material coefficients only (is_material_coefficient).
  std::vector<AdjointParameter> fit = {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Damping};
  // Each coefficient k stays within [k0 / range, k0 range] of its start k0.
  double range = 10.0;
  BoundedLbfgsParams optimizer;
  RecordOptions record;

  void validate() const;  // throws Error naming the field ("fit": an unknown or repeated kind)
};

struct GradientMaterialFitResult {
  Material material;  // the fitted material (the start's values for the coefficients not fitted)
  double loss = 0.0;  // at the fitted material
  BoundedLbfgsStatus status = BoundedLbfgsStatus::IterationBudget;
  int iterations = 0;
  int rollouts = 0;  // forward and backward passes
};

// Fits the scene's material (its start) to the observed positions. Throws Error("loss", ...)
// for observed frames that do not fit the scene, what record_rollout throws, and Error("rollout",
// ...) if a rollout on the way diverges.
GradientMaterialFitResult fit_material_by_gradient(const ResolvedScene& scene,
                                                   const std::vector<FramePositions>& observed,
                                                   const GradientMaterialFitParams& params = {},
                                                   const RolloutInputs& inputs = {});

}  // namespace fnopt
