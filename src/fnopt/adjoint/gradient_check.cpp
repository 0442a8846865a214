#include <fnopt/adjoint/gradient_check.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// The random linear loss: its weights per loss frame, and its value on a rollout.
struct LinearLoss {
  std::vector<int> frames;
  std::vector<VecX> weights;

  double value(const RecordedRollout& rollout) const {
    require(rollout.frame_count() == rollout.scene.scene.frames, "rollout",
            "a perturbed rollout " + rollout.divergence);
    double total = 0.0;
    for (std::size_t i = 0; i < frames.size(); ++i) total += weights[i].dot(rollout.positions[frames[i]]);
    return total;
  }
};

VecX random_vector(Eigen::Index size, std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  VecX v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = normal(random);
  return v;
}

// A random unit direction tilted towards the adjoint gradient g, d = (r/|r| + 2 g/|g|) normalised:
// d.g >= |g|/3, so that no directional derivative is small by chance (then its relative error
// would measure the differences' rounding rather than the gradient).
VecX tilted_direction(const VecX& gradient, std::mt19937_64& random) {
  VecX direction = random_vector(gradient.size(), random).normalized();
  const double norm = gradient.norm();
  if (norm > 0.0) direction += 2.0 * gradient / norm;
  return direction.normalized();
}

// Per-step handle values flattened, and back.
VecX flatten(const std::vector<std::vector<Vec3>>& rows) {
  std::vector<double> values;
  for (const auto& row : rows)
    for (const Vec3& p : row) values.insert(values.end(), p.data(), p.data() + 3);
  return Eigen::Map<const VecX>(values.data(), static_cast<Eigen::Index>(values.size()));
}

std::vector<std::vector<Vec3>> unflatten(const VecX& values, const std::vector<std::vector<Vec3>>& shape) {
  std::vector<std::vector<Vec3>> rows = shape;
  Eigen::Index i = 0;
  for (auto& row : rows)
    for (Vec3& p : row) {
      p = values.segment<3>(i);
      i += 3;
    }
  return rows;
}

void add_comparison(GradientCheckRow& row, double adjoint, double difference) {
  ++row.comparisons;
  row.adjoint_norm = std::hypot(row.adjoint_norm, adjoint);
  row.finite_difference_norm = std::hypot(row.finite_difference_norm, difference);
  const double scale = std::max(std::abs(adjoint), std::abs(difference));
  if (scale > 0.0) row.max_relative_error = std::max(row.max_relative_error, std::abs(adjoint - difference) / scale);
}

}  // namespace

void GradientCheckParams::validate() const {
  require(std::isfinite(material_step) && material_step > 0.0, "material_step", "must be positive");
  require(std::isfinite(vector_step) && vector_step > 0.0, "vector_step", "must be positive");
  require(directions >= 1, "directions", "must be at least 1");
  record.validate();
  require(record.checkpoint_interval == 0, "record.checkpoint_interval",
          "must be 0: the perturbed rollouts start from the base's accelerations, which checkpoints do not keep");
  path.validate();
}

GradientCheckResult gradient_check(const ResolvedScene& scene, const GradientCheckParams& params,
                                   const RolloutInputs& inputs) {
  params.validate();
  const int frames = scene.scene.frames;
  std::mt19937_64 random(params.seed);
  LinearLoss loss;
  loss.frames = params.frames;
  if (loss.frames.empty())
    for (int f = 1; f < frames; ++f) loss.frames.push_back(f);
  for (int f : loss.frames) {
    require(f >= 0 && f < frames, "frames",
            "frame " + std::to_string(f) + " is outside the rollout's 0.." + std::to_string(frames - 1));
    loss.weights.push_back(random_vector(scene.grid.dof_count(), random));
  }

  const RecordedRollout base = record_rollout(scene, params.record, inputs);
  std::vector<FrameGradient> loss_gradient;
  for (std::size_t i = 0; i < loss.frames.size(); ++i) loss_gradient.push_back({loss.frames[i], loss.weights[i]});
  const RolloutGradient gradient = backpropagate(base, loss_gradient);

  GradientCheckResult result;
  result.status = gradient.status;
  result.saddle_steps = static_cast<int>(gradient.saddle_steps.size());
  result.forward_ms = base.forward_ms;
  result.backward_ms = gradient.backward_ms;

  // Every perturbed rollout starts each step from the base rollout's acceleration, so that it
  // follows the base's branch of stationary points (RolloutInputs::start_accelerations).
  RecordOptions perturbed_record = params.record;
  perturbed_record.classify_steps = false;
  const auto loss_at = [&](const ResolvedScene& perturbed, const RolloutInputs& perturbed_inputs) {
    RolloutInputs on_branch = perturbed_inputs;
    on_branch.start_accelerations = base.accelerations;
    return loss.value(record_rollout(perturbed, perturbed_record, on_branch));
  };
  const HandlePath path(params.path, base.step_count(), static_cast<int>(scene.handles.vertices.size()));
  const VecX base_targets = flatten(base.handle_targets);
  const VecX x0 = base.positions.front(), v0 = base.velocities.front();

  // (adjoint . d, loss at p + e d as a function of e) for a vector kind.
  struct VectorKind {
    VecX adjoint;
    std::function<double(const VecX& step)> loss_along;
  };
  const auto vector_kind = [&](AdjointParameter parameter) -> VectorKind {
    switch (parameter) {
      case AdjointParameter::Gravity:
        return {gradient.material.gravity, [&](const VecX& step) {
                  ResolvedScene perturbed = scene;
                  perturbed.scene.gravity += step;
                  return loss_at(perturbed, inputs);
                }};
      case AdjointParameter::HandlePositions:
        return {flatten(gradient.handle_targets), [&](const VecX& step) {
                  RolloutInputs perturbed = inputs;
                  perturbed.handle_targets = unflatten(base_targets + step, base.handle_targets);
                  return loss_at(scene, perturbed);
                }};
      case AdjointParameter::HandlePath:
        return {flatten(path.control_gradient(gradient.handle_targets)), [&](const VecX& step) {
                  RolloutInputs perturbed = inputs;
                  perturbed.handle_targets = unflatten(
                      base_targets + flatten(path.offsets(unflatten(step, path.zero_control_points()))),
                      base.handle_targets);
                  return loss_at(scene, perturbed);
                }};
      case AdjointParameter::InitialPositions:
        return {gradient.initial_positions, [&](const VecX& step) {
                  RolloutInputs perturbed = inputs;
                  perturbed.initial_positions = x0 + step;
                  return loss_at(scene, perturbed);
                }};
      default:
        return {gradient.initial_velocities, [&](const VecX& step) {
                  RolloutInputs perturbed = inputs;
                  perturbed.initial_velocities = v0 + step;
                  return loss_at(scene, perturbed);
                }};
    }
  };

  for (AdjointParameter parameter : params.parameters) {
    GradientCheckRow row;
    row.parameter = parameter;
    if (is_material_coefficient(parameter)) {
      const double e = params.material_step;
      ResolvedScene plus = scene, minus = scene;
      const double k = material_coefficient(plus.scene.material, parameter);
      material_coefficient(plus.scene.material, parameter) = params.log_coordinates ? k * std::exp(e) : k * (1.0 + e);
      material_coefficient(minus.scene.material, parameter) = params.log_coordinates ? k * std::exp(-e) : k * (1.0 - e);
      const double difference = (loss_at(plus, inputs) - loss_at(minus, inputs)) / (2.0 * e);
      const double adjoint = params.log_coordinates ? gradient.log_material.coefficient(parameter)
                                                    : k * gradient.material.coefficient(parameter);
      // Both in log units (k dL/dk) so that the plain form's difference needs no division by k.
      add_comparison(row, adjoint, difference);
    } else {
      const VectorKind kind = vector_kind(parameter);
      for (int d = 0; d < params.directions; ++d) {
        const VecX direction = tilted_direction(kind.adjoint, random);
        const VecX step = params.vector_step * direction;
        const double difference = (kind.loss_along(step) - kind.loss_along(-step)) / (2.0 * params.vector_step);
        add_comparison(row, kind.adjoint.dot(direction), difference);
      }
    }
    result.max_relative_error = std::max(result.max_relative_error, row.max_relative_error);
    result.rows.push_back(row);
  }
  return result;
}

}  // namespace fnopt
