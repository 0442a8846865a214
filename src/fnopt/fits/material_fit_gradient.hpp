#pragma once
// A material fitted by its gradient (docs/design.md §15): the coefficients whose rollout of exact
// steps best reproduces reference rollouts, by projected L-BFGS (bounded_lbfgs.hpp) in the
// logarithms of the coefficients, each within its interval, on the mean over the references of
//   an fnopt rollout on the scene's grid: sum over its frames of sum_i |x_f,i(theta) - x^ref_f,i|^2
//     (adjoint/rollout_loss.hpp's position_loss, vertex for vertex),
//   an ARCSim file: e_CD itself (surface_chamfer_loss) on the frames e_CD reads,
// and its adjoint gradient dL/dlog k (adjoint/rollout_adjoint.hpp), one forward and one backward
// pass per reference and evaluation. The rollout's dynamics depend on the stiffnesses and the
// damping relative to the density (gravity fixed), so density and all three stiffnesses together
// are not identifiable: fit a subset (the default: stretch, shear and damping).
#include <functional>
#include <map>
#include <vector>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/fits/bounded_lbfgs.hpp>
#include <fnopt/fits/material_fit.hpp>

namespace fnopt {

// One reference as the gradient's loss reads it: the rollout frame f (time f dt after the
// reference's first) matched to each reference frame by time (metrics/frame_matching.hpp).
struct GradientFitTarget {
  ResolvedScene scene;                      // frames = the rollout's frame count, the initial one included
  std::vector<FramePositions> positions;    // vertex-for-vertex targets (an fnopt rollout), or
  std::vector<FramePoints> points;          // the reference mesh's e_CD samples (an ARCSim file)
  std::size_t matched = 0;                  // reference frames matched by time, the initial one included
};

// The target of a reference (fit_reference.hpp) for a scene with the `start` material (never the
// reference's own): an fnopt rollout on the scene's grid gives every vertex's target after the
// initial frame; an ARCSim file its mesh's samples on the matched frames e_CD reads, every
// chamfer_stride-th from the first. Throws Error naming the file if no frame after the first matches.
GradientFitTarget gradient_fit_target(const FitReference& reference, const Material& start,
                                      const MaterialFitParams& params);

struct GradientMaterialFitParams {
  // Material coefficients only (is_material_coefficient), each once.
  std::vector<AdjointParameter> fit = {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Damping};
  // Each fitted coefficient's interval (physical units): the compass's (material_fit.hpp) and
  // density's.
  std::map<AdjointParameter, CoefficientRange> ranges = default_ranges();
  BoundedLbfgsParams optimizer = default_optimizer();
  ChamferOptions chamfer;  // e_CD's samples, for ARCSim references
  RecordOptions record;

  static std::map<AdjointParameter, CoefficientRange> default_ranges();
  // 30 iterations; where the rollout passes saddle steps the loss is rough at the scale of the
  // solver's precision near the fit (docs/design.md §15): a search that cannot descend there would
  // take 30 halvings, a rollout each, before it says so, and one that still can gains nothing a fit
  // can use, so 10 halvings and a stop below a relative decrease of 1e-4. The first step moves a
  // coefficient by a factor e at most, as the compass's first poll: the gradient's size says
  // nothing about how far to go.
  static BoundedLbfgsParams default_optimizer();
  void validate() const;  // throws Error naming the field ("fit": an unknown or repeated kind)
};

struct GradientMaterialFitResult {
  Material material;  // the fitted material (the start's values for the coefficients not fitted)
  double start_loss = 0.0, loss = 0.0;
  BoundedLbfgsStatus status = BoundedLbfgsStatus::IterationBudget;
  int iterations = 0;
  int rollouts = 0;  // recorded forward passes, each with its backward pass
};

// Called after each evaluation with its count, the material and the mean loss (+inf where a
// rollout diverged).
using GradientFitCallback = std::function<void(int evaluation, const Material& material, double loss)>;

// Fits from `start`. A trial material whose rollout diverges has an infinite loss, which the line
// search steps back from. Throws what record_rollout throws.
GradientMaterialFitResult fit_material_by_gradient(const std::vector<GradientFitTarget>& targets,
                                                   const Material& start, const GradientMaterialFitParams& params = {},
                                                   const GradientFitCallback& on_evaluation = {});

}  // namespace fnopt
