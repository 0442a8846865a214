#pragma once
// A material fitted by its gradient (docs/design.md §15): the coefficients whose rollout of exact
// steps best reproduces reference rollouts, by a projected Levenberg-Marquardt iteration
// (bounded_gauss_newton.hpp) in the logarithms of the coefficients, each within its interval, on
// the mean over the references of
//   an fnopt rollout on the scene's grid: sum over its frames of sum_i |x_f,i(theta) - x^ref_f,i|^2
//     (adjoint/rollout_loss.hpp's position_loss, vertex for vertex),
//   an ARCSim file: e_CD itself (surface_chamfer_loss) on the frames e_CD reads.
// Each evaluation is a recorded forward pass and one tangent pass along every fitted ln k
// (StepLinearization::advance_tangent, the source k dg/dk): J_f = dx_f/dln k at every frame, so the
// gradient J^T dL/dx and the Gauss-Newton model G = sum_f J_f^T W_f J_f (W_f the loss's
// gauss_newton_weights) come together, for one factorisation per step and a solve per coefficient.
//
// A buckling cloth makes the loss over a long horizon rough: a coefficient changed in its fourth
// digit can switch the folds' branch late in the rollout, and a fit from far away then ends in a
// wrong basin (docs/design.md §15). The early frames have not branched yet, so the fit runs in
// stages (a continuation in the horizon): first on a fraction of every target's steps, each stage
// starting where the one before ended, then on the whole.
//
// What positions determine: with gravity fixed, a step's stationarity divided by the density depends
// on the stiffnesses and the damping relative to it, so scaling the stiffnesses and the density
// together leaves every rollout as it is. The fit therefore holds the density (the start's, or one
// a given mass sets) and fits stretch/rho, shear/rho, bend/rho and the damping; naming the density
// is an error.
#include <functional>
#include <map>
#include <vector>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/fits/bounded_gauss_newton.hpp>
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
  std::vector<AdjointParameter> fit = {AdjointParameter::Stretch, AdjointParameter::Shear, AdjointParameter::Bend,
                                       AdjointParameter::Damping};
  // Each fitted coefficient's interval (physical units): the compass's (material_fit.hpp).
  std::map<AdjointParameter, CoefficientRange> ranges = default_ranges();
  BoundedGaussNewtonParams optimizer = default_optimizer();  // max_evaluations: over every stage
  // The stages before the whole horizon, as fractions of every target's steps, ascending in (0, 1);
  // empty: the whole horizon at once.
  std::vector<double> horizons = {1.0 / 3.0};
  ChamferOptions chamfer;  // e_CD's samples, for ARCSim references
  // The forward passes' exact steps, their Hessians not classified: the tangent pass factorizes each
  // step's Hessian itself (and finds a singular one), so a classification would factorize it twice.
  RecordOptions record = [] {
    RecordOptions options;
    options.classify_steps = false;
    return options;
  }();

  static std::map<AdjointParameter, CoefficientRange> default_ranges();
  // 30 evaluations; the first step moves a coefficient by at most the compass's first poll, every
  // step by a factor e at most; stationary once the Gauss-Newton step changes no coefficient by
  // more than 1e-6 (relative).
  static BoundedGaussNewtonParams default_optimizer();
  // A stage before the last only has to bring the fit into the whole horizon's basin: it stops once
  // its step changes no coefficient by more than kStageStepTolerance (relative), or once its
  // Gauss-Newton model promises less than kStageDecreaseTolerance of its loss (the rest is the noise
  // floor of its short horizon, where a coefficient it barely sees creeps; design.md §15).
  static constexpr double kStageStepTolerance = 1e-3;
  static constexpr double kStageDecreaseTolerance = 0.1;
  void validate() const;  // throws Error naming the field ("fit": an unknown, repeated or unidentifiable kind;
                          // "horizons": not ascending in (0, 1))
};

struct GradientMaterialFitResult {
  Material material;  // the fitted material (the start's values for the coefficients not fitted)
  double start_loss = 0.0, loss = 0.0;  // on the whole horizon: at the last stage's start, and fitted
  BoundedGaussNewtonStatus status = BoundedGaussNewtonStatus::EvaluationBudget;  // the last stage's
  int iterations = 0;                    // steps, over every stage
  int rollouts = 0;  // recorded forward passes, each with its tangent pass, over every stage
  // Per fitted coefficient, in params.fit's order: its standard deviation in ln k (the relative
  // uncertainty), sqrt(s^2 (J^T J)^-1_ii) with the residual variance s^2 = sum r^2 / (N - p) over
  // the N residual components (position losses; for e_CD the same formula on its samples).
  std::vector<double> uncertainty;
  std::vector<char> at_bound;  // per fitted coefficient: it ended at an end of its interval
};

// Called after each evaluation with its count (over every stage), the stage's horizon (the fraction
// of the steps, 1 for the whole), the material and the mean loss (+inf where a rollout diverged).
using GradientFitCallback =
    std::function<void(int evaluation, double horizon, const Material& material, double loss)>;

// Fits from `start`. A trial material whose rollout diverges has an infinite loss, which the line
// search steps back from. Throws what record_rollout throws.
GradientMaterialFitResult fit_material_by_gradient(const std::vector<GradientFitTarget>& targets,
                                                   const Material& start, const GradientMaterialFitParams& params = {},
                                                   const GradientFitCallback& on_evaluation = {});

}  // namespace fnopt
