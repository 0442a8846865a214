#pragma once
// The adjoint checked against central differences of the rollout itself (docs/design.md §15),
// one row per parameter kind, for `fnopt gradcheck` and the tests.
//
// The loss is a fixed random linear functional of the positions, L = sum_{f in frames} w_f . x_f
// (w_f standard normal, from the seed), whose dL/dx_f = w_f is the same at every point, so a
// difference measures the rollout alone. Each perturbed rollout is recorded like the base one
// (Newton to RecordOptions' tight tolerance, then exact Newton steps), every step started from the
// base rollout's acceleration, so that it lands on the continuation of the base's stationary
// point rather than on another minimum of a step with several (RolloutInputs::
// start_accelerations). Per kind:
//  * a material coefficient k: dL/dk against (L(k(1 + e)) - L(k(1 - e))) / (2 e k), or in log
//    coordinates dL/dlog k against (L(k exp(e)) - L(k exp(-e))) / (2 e), e = material_step;
//  * a vector (gravity, the handle targets at every step, the handle path's control points, the
//    initial positions or velocities): along `directions` random unit directions d tilted towards
//    the adjoint gradient g (d = (r/|r| + 2 g/|g|) normalised, r standard normal, so that
//    d.g >= |g|/3 and no derivative is small by chance), <g, d> against
//    (L(p + e d) - L(p - e d)) / (2 e), e = vector_step.
// The relative error of a comparison is |adjoint - difference| / max(|adjoint|, |difference|).
//
// Where the rollout is nearly chaotic (a buckling cloth), its exact derivative holds only for
// perturbations far below any step a difference can take, and the differences do not settle as the
// step shrinks. So each comparison sweeps the step over e 10^k, k = sweep_decades .. -sweep_decades:
// the differences have settled where two at neighbouring steps agree within settle_tolerance, and the
// comparison takes the pair that agrees best (its smaller step's difference). A kind is unreliable
// where one of its comparisons did not settle, or settled away from the adjoint by more than
// `agreement`; its row says why (docs/design.md §15).
#include <cstdint>
#include <string>
#include <vector>

#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>

namespace fnopt {

struct GradientCheckParams {
  std::vector<AdjointParameter> parameters = all_adjoint_parameters();
  std::vector<int> frames;       // the loss's frames; empty: every frame after the first
  bool log_coordinates = true;   // material coefficients in log coordinates
  // The steps balance truncation (e^2 times the rollout's third derivative) against the forward
  // solves' rounding (divided by e). A vector step must stay smaller than the material's: a random
  // perturbation of a flat cloth's initial positions moves it along its soft out-of-plane modes,
  // whose response leaves the linear range first (docs/design.md §15).
  double material_step = 1e-5;   // e: relative, or additive in log k
  double vector_step = 1e-7;     // e along a unit direction, in the parameter's unit (m, m/s, m/s^2)
  int directions = 2;            // random directions per vector kind
  int sweep_decades = 2;         // steps e 10^k, |k| <= sweep_decades (0: e alone, no settling verdict)
  double settle_tolerance = 1e-4;  // relative: two neighbouring steps' differences that agree have settled
  double agreement = 1e-4;       // relative: the largest error of a reliable kind
  std::uint64_t seed = 1;        // of the loss's weights and the directions
  RecordOptions record;          // every rollout's, the base's and the perturbed ones (no checkpoints)
  HandlePathParams path;         // the handle path's basis (the HandlePath kind), offsets from zero

  void validate() const;  // throws Error naming the field
};

struct GradientCheckRow {
  AdjointParameter parameter = AdjointParameter::Stretch;
  int comparisons = 0;
  double adjoint_norm = 0.0;            // of the compared adjoint values
  double finite_difference_norm = 0.0;  // of the central differences
  double max_relative_error = 0.0;      // against each comparison's settled (or only) difference
  bool settled = true;                  // every comparison's differences settled (always, without a sweep)
  // The backward pass's verdict for this kind (GradientVerdict::radius of its gradient): the
  // perturbation below which the gradient holds, in the kind's step unit (relative for a material
  // coefficient, the parameter's unit along a unit direction for a vector).
  double valid_radius = 0.0;
  // Empty where the kind agrees; else why it is unreliable: its differences did not settle (with the
  // sweep of its first such comparison), or they settled away from the adjoint (its largest error).
  std::string unreliable;
};

struct GradientCheckResult {
  std::vector<GradientCheckRow> rows;  // in params.parameters' order
  double max_relative_error = 0.0;     // over the rows
  AdjointStatus status = AdjointStatus::Exact;  // the base rollout's backward pass
  GradientVerdict verdict;                      // and its verdict
  int saddle_steps = 0;
  double forward_ms = 0.0;   // the base rollout's forward pass
  double backward_ms = 0.0;  // its backward pass
};

// Records the scene's rollout from `inputs`, backpropagates the random linear loss and compares
// each kind with central differences. Throws what record_rollout and backpropagate throw, and
// Error("frames", ...) for a loss frame outside the rollout.
GradientCheckResult gradient_check(const ResolvedScene& scene, const GradientCheckParams& params = {},
                                   const RolloutInputs& inputs = {});

}  // namespace fnopt
