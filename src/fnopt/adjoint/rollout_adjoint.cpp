#include <fnopt/adjoint/rollout_adjoint.hpp>

#include <algorithm>
#include <chrono>

#include <fnopt/adjoint/step_states.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// The loss gradient's terms summed per frame (empty where a frame has none). Throws
// Error("loss", ...) for a frame outside the rollout or a gradient of the wrong size.
std::vector<VecX> loss_by_frame(const std::vector<FrameGradient>& loss_gradient, int frames, Eigen::Index dofs) {
  std::vector<VecX> loss(frames);
  for (const FrameGradient& term : loss_gradient) {
    require(term.frame >= 0 && term.frame < frames, "loss",
            "frame " + std::to_string(term.frame) + " is outside the rollout's 0.." + std::to_string(frames - 1));
    require(term.gradient.size() == dofs, "loss",
            "frame " + std::to_string(term.frame) + ": expected " + std::to_string(dofs) +
                " values (3 per vertex), got " + std::to_string(term.gradient.size()));
    if (loss[term.frame].size() == 0)
      loss[term.frame] = term.gradient;
    else
      loss[term.frame] += term.gradient;
  }
  return loss;
}

// A complete pass through unconverged or saddle steps says so; the material's gradient also in
// ln k (dL/dln k = k dL/dk).
void finish_status_and_material(RolloutGradient& out, const Material& material) {
  if (out.status == AdjointStatus::Exact) {
    if (!out.unconverged_steps.empty())
      out.status = AdjointStatus::Unconverged;
    else if (!out.saddle_steps.empty())
      out.status = AdjointStatus::ThroughSaddles;
  }
  out.log_material = out.material;
  out.log_material.stretch *= material.stretch;
  out.log_material.shear *= material.shear;
  out.log_material.bend *= material.bend;
  out.log_material.density *= material.density;
  out.log_material.damping *= material.damping;
}

}  // namespace

const char* to_string(AdjointStatus status) {
  switch (status) {
    case AdjointStatus::Exact:
      return "exact";
    case AdjointStatus::ThroughSaddles:
      return "through-saddles";
    case AdjointStatus::Unconverged:
      return "unconverged";
    case AdjointStatus::StoppedAtSaddle:
      return "stopped-at-saddle";
    case AdjointStatus::Singular:
      return "singular";
  }
  return "unknown";
}

bool is_complete(AdjointStatus status) {
  return status == AdjointStatus::Exact || status == AdjointStatus::ThroughSaddles ||
         status == AdjointStatus::Unconverged;
}

RolloutGradient backpropagate(const RecordedRollout& rollout, const std::vector<FrameGradient>& loss_gradient,
                              const AdjointParams& params) {
  require(!rollout.empty(), "rollout", "no recorded forward pass (record_rollout gives one)");
  require(!rollout.diverged, "rollout", "the forward pass " + rollout.divergence + ": no gradient through it");
  const auto begin = std::chrono::steady_clock::now();
  const Eigen::Index dofs = rollout.positions.front().size();
  const std::vector<VecX> loss = loss_by_frame(loss_gradient, rollout.frame_count(), dofs);

  const double dt = rollout.scene.scene.dt;
  const int handles = static_cast<int>(rollout.scene.handles.vertices.size());
  StepLinearization step(rollout.scene);
  StepStates states(rollout);
  RolloutGradient out;
  out.handle_targets.assign(rollout.step_count(), std::vector<Vec3>(handles, Vec3::Zero()));
  VecX xbar = loss.back().size() ? loss.back() : VecX::Zero(dofs);
  VecX vbar = VecX::Zero(dofs);
  VecX abar, lambda, k_lambda;
  for (int s = rollout.step_count() - 1; s >= 0; --s) {
    if (!is_converged(rollout.steps[s].status)) out.unconverged_steps.insert(out.unconverged_steps.begin(), s);
    states.load(s);
    step.set_released(rollout.steps[s].released);
    const StepStationarity stationarity = step.linearize(states.x(), states.v(), states.a(), s * dt);
    if (stationarity == StepStationarity::Singular) {
      out.status = AdjointStatus::Singular;
      out.singular_step = s;
      break;
    }
    if (stationarity == StepStationarity::Saddle) {
      out.saddle_steps.insert(out.saddle_steps.begin(), s);
      if (!params.solve_at_saddles) {
        out.status = AdjointStatus::StoppedAtSaddle;
        break;
      }
    }
    abar = dt * dt * xbar + dt * vbar;
    step.solve(abar, lambda);
    step.stiffness_product(lambda, k_lambda);  // dt^4 K lambda
    out.material += step.material_gradient(lambda);

    // x_{s+1} and v_{s+1} depend on x_s, v_s directly, and through a_F (lambda) and a_H.
    vbar += dt * xbar;
    xbar -= k_lambda / (dt * dt);
    step.subtract_friction_start_product(lambda, xbar);
    vbar -= k_lambda / dt;
    for (Eigen::Index k = 0; k < dofs / 3; ++k)
      vbar.segment<3>(3 * k) -= step.damping_weight(static_cast<int>(k)) * lambda.segment<3>(3 * k);
    for (int h = 0; h < handles && !rollout.steps[s].released; ++h) {
      const int k = rollout.scene.handles.vertices[h];
      const Vec3 abar_h = abar.segment<3>(3 * k) - k_lambda.segment<3>(3 * k);
      out.handle_targets[s][h] = abar_h / (dt * dt);
      xbar.segment<3>(3 * k) -= abar_h / (dt * dt);
      vbar.segment<3>(3 * k) -= abar_h / dt;
    }
    if (loss[s].size()) xbar += loss[s];
  }
  out.initial_positions = std::move(xbar);
  out.initial_velocities = std::move(vbar);
  finish_status_and_material(out, rollout.scene.scene.material);
  out.resimulated_steps = states.resimulated_steps();
  out.resimulation_error = states.resimulation_error();
  out.factorizations = step.factorizations();
  out.solves = step.solves();
  out.backward_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  if (params.verdict && is_complete(out.status)) {
    int last_loss_frame = 0;
    for (const FrameGradient& term : loss_gradient) last_loss_frame = std::max(last_loss_frame, term.frame);
    out.verdict = gradient_verdict(rollout, out.initial_positions, last_loss_frame);
  }
  return out;
}

}  // namespace fnopt
