#include <fnopt/adjoint/gradient_verdict.hpp>

#include <chrono>
#include <cmath>
#include <limits>

#include <fnopt/adjoint/step_linearization.hpp>
#include <fnopt/adjoint/step_states.hpp>

namespace fnopt {
namespace {

// The second difference's move, as a fraction of an edge.
constexpr double kProbeFraction = 1e-4;
// A frame's linear prediction holds while its second-order term is at most this fraction of its
// first-order one.
constexpr double kLinearFraction = 0.1;
// At R_0 the second-order term is kLinearFraction of the first: the derivative has changed by twice that.
constexpr double kSecondOrderSlope = 2.0 * kLinearFraction;
// The tangents are rescaled (their true values kept as a logarithm) once the first passes this.
constexpr double kRescaleAbove = 1e100;

// The rollout's first- and second-order tangents along a perturbation e d of its start positions,
// x_s(e) = x_s + e dx_s + e^2/2 ddx_s + ..., the handles' targets held. Differentiating g_F = 0
// (step_linearization.hpp) twice along e, only P is not quadratic in the positions, so the second
// order is the first's linear step with the source dt^2 d^3P[dx_{s+1}, dx_{s+1}]
// (StepLinearization::advance_tangent, third_derivative).
class StartTangents {
 public:
  explicit StartTangents(const VecX& direction)
      : dx_(direction), dv_(VecX::Zero(direction.size())), ddx_(VecX::Zero(direction.size())),
        ddv_(VecX::Zero(direction.size())) {}

  // Advances over step s, linearised in `step`: dx() and ddx() are then x_{s+1}'s.
  void advance(StepLinearization& step, double probe) {
    step.advance_tangent(dx_, dv_, nullptr);
    step.third_derivative(dx_, probe, source_);
    step.advance_tangent(ddx_, ddv_, &source_);
    const double norm = dx_.norm();
    if (norm > kRescaleAbove) {  // keep dx, ddx as (scale dx, scale^2 ddx)
      dx_ /= norm, dv_ /= norm;
      ddx_ /= norm * norm, ddv_ /= norm * norm;
      log_scale_ += std::log(norm);
    }
  }
  // e at which x_{s+1}'s second-order term is `fraction` of its first-order one.
  double linear_radius(double fraction) const {
    const double second = ddx_.norm();
    if (second == 0.0) return std::numeric_limits<double>::infinity();
    return 2.0 * fraction * dx_.norm() / second * std::exp(-log_scale_);
  }
  double log_growth() const { return std::log(dx_.norm()) + log_scale_; }  // ln |dx_{s+1}|

 private:
  VecX dx_, dv_, ddx_, ddv_, source_;
  double log_scale_ = 0.0;
};

}  // namespace

const char* to_string(GradientConditioning conditioning) {
  switch (conditioning) {
    case GradientConditioning::NotMeasured:
      return "not-measured";
    case GradientConditioning::WellConditioned:
      return "well-conditioned";
    case GradientConditioning::IllConditioned:
      return "ill-conditioned";
    case GradientConditioning::BelowPrecision:
      return "below-precision";
  }
  return "unknown";
}

double GradientVerdict::radius(double gradient_norm) const {
  return gradient_norm > 0.0 ? loss_radius / gradient_norm : std::numeric_limits<double>::infinity();
}

GradientVerdict gradient_verdict(const RecordedRollout& rollout, const VecX& start_gradient, int last_loss_frame) {
  const auto begin = std::chrono::steady_clock::now();
  GradientVerdict verdict;
  const double spacing = rollout.scene.grid.spacing;
  const double gradient_norm = start_gradient.norm();
  verdict.start_radius = std::numeric_limits<double>::infinity();
  if (gradient_norm > 0.0) {
    StepLinearization step(rollout.scene);
    StepStates states(rollout);
    StartTangents tangents(start_gradient / gradient_norm);
    const double root_dofs = std::sqrt(static_cast<double>(start_gradient.size()));
    const int steps = std::min(last_loss_frame, rollout.step_count());
    for (int s = 0; s < steps; ++s) {
      states.load(s);
      step.set_released(rollout.steps[s].released);
      if (step.linearize(states.x(), states.v(), states.a(), s * rollout.scene.scene.dt) ==
          StepStationarity::Singular)
        return {};  // the backward pass stops there too
      tangents.advance(step, kProbeFraction * spacing);
      const double dt = rollout.scene.scene.dt;
      verdict.forward_error += dt * dt * rollout.steps[s].residual_acceleration * root_dofs *
                               std::exp(-tangents.log_growth());
      verdict.log_growth = std::max(verdict.log_growth, tangents.log_growth());
      const double radius = tangents.linear_radius(kLinearFraction);
      if (radius < verdict.start_radius) {
        verdict.start_radius = radius;
        verdict.binding_frame = s + 1;
      }
    }
  }
  verdict.loss_radius = verdict.start_radius * gradient_norm;
  verdict.precision = kSecondOrderSlope * verdict.forward_error / verdict.start_radius;
  if (verdict.precision >= 1.0)
    verdict.conditioning = GradientConditioning::BelowPrecision;
  else if (verdict.start_radius >= GradientVerdict::well_conditioned_fraction * spacing)
    verdict.conditioning = GradientConditioning::WellConditioned;
  else
    verdict.conditioning = GradientConditioning::IllConditioned;
  verdict.measure_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  return verdict;
}

}  // namespace fnopt
