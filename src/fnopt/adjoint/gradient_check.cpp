#include <fnopt/adjoint/gradient_check.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <random>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

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

double relative_distance(double a, double b) {
  const double scale = std::max(std::abs(a), std::abs(b));
  return scale > 0.0 ? std::abs(a - b) / scale : 0.0;
}

// The central differences of one comparison at its steps, largest first.
struct Sweep {
  std::vector<double> steps, differences;

  // The index of the difference the comparison takes: of the neighbouring pair that agrees best, the
  // smaller step's (the only one without a sweep); and whether that pair agrees within `tolerance`.
  std::size_t settled(double tolerance, bool& settles) const {
    settles = true;
    if (differences.size() < 2) return 0;
    std::size_t best = 1;
    for (std::size_t k = 1; k < differences.size(); ++k)
      if (relative_distance(differences[k - 1], differences[k]) <
          relative_distance(differences[best - 1], differences[best]))
        best = k;
    settles = relative_distance(differences[best - 1], differences[best]) <= tolerance;
    return best;
  }

  std::string text() const {
    std::string out;
    for (std::size_t k = 0; k < steps.size(); ++k)
      out += (k ? ", " : "") + number_text(differences[k]) + " at " + number_text(steps[k]);
    return out;
  }
};

// Adds one comparison's adjoint value and its sweep to the row; the row keeps, as its verdict, the
// first unsettled sweep or else the largest disagreement.
void add_comparison(GradientCheckRow& row, double adjoint, const Sweep& sweep, const GradientCheckParams& params) {
  ++row.comparisons;
  bool settles = true;
  const double difference = sweep.differences[sweep.settled(params.settle_tolerance, settles)];
  row.adjoint_norm = std::hypot(row.adjoint_norm, adjoint);
  row.finite_difference_norm = std::hypot(row.finite_difference_norm, difference);
  const double error = relative_distance(adjoint, difference);
  if (!settles && row.settled) {
    row.settled = false;
    row.unreliable = "central differences do not settle as the step shrinks (" + sweep.text() + "; the adjoint " +
                     number_text(adjoint) + ")";
  } else if (settles && row.settled && error > params.agreement && error > row.max_relative_error) {
    row.unreliable = "the adjoint's " + number_text(adjoint) + " against central differences' " +
                     number_text(difference) + (sweep.steps.size() > 1 ? ", where they settled" : "") +
                     " (relative error " + number_text(error) + ")";
  }
  row.max_relative_error = std::max(row.max_relative_error, error);
}

}  // namespace

void GradientCheckParams::validate() const {
  require(std::isfinite(material_step) && material_step > 0.0, "material_step", "must be positive");
  require(std::isfinite(vector_step) && vector_step > 0.0, "vector_step", "must be positive");
  require(directions >= 1, "directions", "must be at least 1");
  require(sweep_decades >= 0 && sweep_decades <= 6, "sweep_decades", "must be in 0..6");
  require(std::isfinite(settle_tolerance) && settle_tolerance > 0.0, "settle_tolerance", "must be positive");
  require(std::isfinite(agreement) && agreement > 0.0, "agreement", "must be positive");
  record.validate();
  require(record.checkpoint_interval == 0, "record.checkpoint_interval",
          "must be 0: the perturbed rollouts start from the base's accelerations, which checkpoints do not keep");
  path.validate();
}

namespace {

// The check of one scene: the base rollout, its adjoint gradient of the random linear loss, and
// the loss of perturbed rollouts, each starting every step from the base rollout's acceleration
// so that it follows the base's branch of stationary points (RolloutInputs::start_accelerations).
class GradientChecker {
 public:
  GradientChecker(const ResolvedScene& scene, const GradientCheckParams& params, const RolloutInputs& inputs)
      : scene_(scene), params_(params), inputs_(inputs), random_(params.seed) {
    const int frames = scene.scene.frames;
    loss_.frames = params.frames;
    if (loss_.frames.empty())
      for (int f = 1; f < frames; ++f) loss_.frames.push_back(f);
    for (int f : loss_.frames) {
      require(f >= 0 && f < frames, "frames",
              "frame " + std::to_string(f) + " is outside the rollout's 0.." + std::to_string(frames - 1));
      loss_.weights.push_back(random_vector(scene.grid.dof_count(), random_));
    }
    base_ = record_rollout(scene, params.record, inputs);
    std::vector<FrameGradient> loss_gradient;
    for (std::size_t i = 0; i < loss_.frames.size(); ++i) loss_gradient.push_back({loss_.frames[i], loss_.weights[i]});
    gradient_ = backpropagate(base_, loss_gradient);
    perturbed_record_ = params.record;
    perturbed_record_.classify_steps = false;
    path_.emplace(params.path, base_.step_count(), static_cast<int>(scene.handles.vertices.size()));
    base_targets_ = flatten(base_.handle_targets);
  }

  const RecordedRollout& base() const { return base_; }
  const RolloutGradient& gradient() const { return gradient_; }

  GradientCheckRow check(AdjointParameter parameter) {
    GradientCheckRow row = compare(parameter);
    if (!row.unreliable.empty() && gradient_.verdict.conditioning != GradientConditioning::NotMeasured)
      row.unreliable += "; the backward pass's verdict: " + std::string(to_string(gradient_.verdict.conditioning)) +
                        ", valid below " + number_text(row.valid_radius);
    return row;
  }

 private:
  GradientCheckRow compare(AdjointParameter parameter) {
    GradientCheckRow row;
    row.parameter = parameter;
    if (is_material_coefficient(parameter)) {
      check_material(parameter, row);
      return row;
    }
    const VectorKind kind = vector_kind(parameter);
    row.valid_radius = gradient_.verdict.radius(kind.adjoint.norm());
    for (int d = 0; d < params_.directions; ++d) {
      const VecX direction = tilted_direction(kind.adjoint, random_);
      add_comparison(row, kind.adjoint.dot(direction), sweep(params_.vector_step, [&](double e) {
                       return (kind.loss_along(e * direction) - kind.loss_along(-e * direction)) / (2.0 * e);
                     }), params_);
    }
    return row;
  }

  // (adjoint . d, loss at p + e d as a function of e) for a vector kind.
  struct VectorKind {
    VecX adjoint;
    std::function<double(const VecX& step)> loss_along;
  };

  double loss_at(const ResolvedScene& perturbed, const RolloutInputs& perturbed_inputs) const {
    RolloutInputs on_branch = perturbed_inputs;
    on_branch.start_accelerations = base_.accelerations;
    return loss_.value(record_rollout(perturbed, perturbed_record_, on_branch));
  }

  // The central difference `at(e)` at the steps base 10^k, k = sweep_decades .. -sweep_decades.
  template <class Difference>
  Sweep sweep(double base, Difference&& at) const {
    Sweep s;
    for (int k = params_.sweep_decades; k >= -params_.sweep_decades; --k) {
      s.steps.push_back(base * std::pow(10.0, k));
      s.differences.push_back(at(s.steps.back()));
    }
    return s;
  }

  // Central differences in k (or ln k) against the adjoint, both in log units (k dL/dk) so that the
  // plain form's difference needs no division by k.
  void check_material(AdjointParameter parameter, GradientCheckRow& row) const {
    const double k = material_coefficient(scene_.scene.material, parameter);
    const Sweep differences = sweep(params_.material_step, [&](double e) {
      ResolvedScene plus = scene_, minus = scene_;
      material_coefficient(plus.scene.material, parameter) = params_.log_coordinates ? k * std::exp(e) : k * (1.0 + e);
      material_coefficient(minus.scene.material, parameter) =
          params_.log_coordinates ? k * std::exp(-e) : k * (1.0 - e);
      return (loss_at(plus, inputs_) - loss_at(minus, inputs_)) / (2.0 * e);
    });
    const double adjoint = params_.log_coordinates ? gradient_.log_material.coefficient(parameter)
                                                   : k * gradient_.material.coefficient(parameter);
    row.valid_radius = gradient_.verdict.radius(std::abs(adjoint));
    add_comparison(row, adjoint, differences, params_);
  }

  VectorKind vector_kind(AdjointParameter parameter) const {
    switch (parameter) {
      case AdjointParameter::Gravity:
        return {gradient_.material.gravity, [this](const VecX& step) {
                  ResolvedScene perturbed = scene_;
                  perturbed.scene.gravity += step;
                  return loss_at(perturbed, inputs_);
                }};
      case AdjointParameter::HandlePositions:
        return {flatten(gradient_.handle_targets), [this](const VecX& step) {
                  RolloutInputs perturbed = inputs_;
                  perturbed.handle_targets = unflatten(base_targets_ + step, base_.handle_targets);
                  return loss_at(scene_, perturbed);
                }};
      case AdjointParameter::HandlePath:
        return {flatten(path_->control_gradient(gradient_.handle_targets)), [this](const VecX& step) {
                  RolloutInputs perturbed = inputs_;
                  perturbed.handle_targets = unflatten(
                      base_targets_ + flatten(path_->offsets(unflatten(step, path_->zero_control_points()))),
                      base_.handle_targets);
                  return loss_at(scene_, perturbed);
                }};
      case AdjointParameter::InitialPositions:
        return {gradient_.initial_positions, [this](const VecX& step) {
                  RolloutInputs perturbed = inputs_;
                  perturbed.initial_positions = base_.positions.front() + step;
                  return loss_at(scene_, perturbed);
                }};
      default:
        return {gradient_.initial_velocities, [this](const VecX& step) {
                  RolloutInputs perturbed = inputs_;
                  perturbed.initial_velocities = base_.velocities.front() + step;
                  return loss_at(scene_, perturbed);
                }};
    }
  }

  const ResolvedScene& scene_;
  const GradientCheckParams& params_;
  const RolloutInputs& inputs_;
  std::mt19937_64 random_;
  LinearLoss loss_;
  RecordedRollout base_;
  RolloutGradient gradient_;
  RecordOptions perturbed_record_;
  std::optional<HandlePath> path_;
  VecX base_targets_;
};

}  // namespace

GradientCheckResult gradient_check(const ResolvedScene& scene, const GradientCheckParams& params,
                                   const RolloutInputs& inputs) {
  params.validate();
  GradientChecker checker(scene, params, inputs);
  GradientCheckResult result;
  result.status = checker.gradient().status;
  result.verdict = checker.gradient().verdict;
  result.saddle_steps = static_cast<int>(checker.gradient().saddle_steps.size());
  result.forward_ms = checker.base().forward_ms;
  result.backward_ms = checker.gradient().backward_ms;
  for (AdjointParameter parameter : params.parameters) {
    const GradientCheckRow row = checker.check(parameter);
    result.max_relative_error = std::max(result.max_relative_error, row.max_relative_error);
    result.rows.push_back(row);
  }
  return result;
}

}  // namespace fnopt
