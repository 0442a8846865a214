#include <fnopt/fits/bounded_gauss_newton.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include <fnopt/fits/box_bounds.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// Added to G's diagonal, relative to its largest entry, so that the undamped step exists where G is
// singular (a variable the loss does not see).
constexpr double kDiagonalFloor = 1e-12;
// The most mu shrinks after a step whose model was right (Nielsen's rule: 1/3): a variable the loss
// barely sees moves only once mu is below its share of G's diagonal, and waits fewer evaluations.
constexpr double kFastestShrink = 0.1;

// (G_ff + mu D) d_f = -g_f on the free variables (d_i = 0 on the held ones), D = (max diag G) I:
// Levenberg's damping, not Marquardt's diag G, so that a variable the loss barely sees moves only
// once mu has fallen, after the ones it sees well have settled (a damping by diag G would give it a
// long step from the start, while the others' errors still decide where it should go).
Eigen::VectorXd damped_step(const VecX& g, const Eigen::MatrixXd& G, const std::vector<char>& held, double mu) {
  const Eigen::Index n = g.size();
  const double scale = std::max(G.diagonal().maxCoeff(), 0.0);
  Eigen::MatrixXd A = G;
  VecX b = -g;
  for (Eigen::Index i = 0; i < n; ++i) {
    A(i, i) += mu * scale + kDiagonalFloor * scale;
    if (held[i]) {
      A.row(i).setZero();
      A.col(i).setZero();
      A(i, i) = 1.0;
      b[i] = 0.0;
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> factor(A);
  VecX d = factor.solve(b);
  if (!d.allFinite()) d.setZero();
  return d;
}

// The model's decrease along s, -(g.s + s.G s / 2).
double model_decrease(const VecX& g, const Eigen::MatrixXd& G, const VecX& s) {
  return -(g.dot(s) + 0.5 * s.dot(G * s));
}

}  // namespace

void BoundedGaussNewtonParams::validate() const {
  require(max_evaluations >= 1, "max_evaluations", "must be at least 1");
  require(std::isfinite(step_tolerance) && step_tolerance > 0.0, "step_tolerance", "must be positive");
  require(std::isfinite(decrease_tolerance) && decrease_tolerance >= 0.0 && decrease_tolerance < 1.0,
          "decrease_tolerance", "must lie in [0, 1)");
  require(std::isfinite(initial_damping) && initial_damping >= 0.0, "initial_damping", "must be at least 0");
  require(std::isfinite(max_damping) && max_damping > initial_damping, "max_damping", "must exceed initial_damping");
  require(std::isfinite(first_step) && first_step >= 0.0, "first_step", "must be at least 0");
  require(std::isfinite(max_step) && max_step >= 0.0, "max_step", "must be at least 0");
}

const char* to_string(BoundedGaussNewtonStatus status) {
  switch (status) {
    case BoundedGaussNewtonStatus::Stationary:
      return "stationary";
    case BoundedGaussNewtonStatus::Settled:
      return "settled";
    case BoundedGaussNewtonStatus::NoDecrease:
      return "no-decrease";
    case BoundedGaussNewtonStatus::EvaluationBudget:
      return "evaluation-budget";
    case BoundedGaussNewtonStatus::NonFinite:
      return "non-finite";
  }
  return "unknown";
}

BoundedGaussNewtonResult minimize_by_gauss_newton(const GaussNewtonObjective& f, const VecX& x0, const VecX& lower,
                                                  const VecX& upper, const BoundedGaussNewtonParams& params) {
  params.validate();
  check_box(x0, lower, upper);
  BoundedGaussNewtonResult result;
  result.x = project_to_box(x0, lower, upper);
  result.value = f(result.x, result.gradient, result.model);
  result.evaluations = 1;
  if (!std::isfinite(result.value) || !result.gradient.allFinite() || !result.model.allFinite()) {
    result.status = BoundedGaussNewtonStatus::NonFinite;
    return result;
  }
  double mu = params.initial_damping, growth = 2.0;
  VecX gradient;
  Eigen::MatrixXd model;
  while (true) {
    const std::vector<char> held = held_at_bounds(result.x, result.gradient, lower, upper);
    const VecX newton = damped_step(result.gradient, result.model, held, 0.0);
    if (newton.cwiseAbs().maxCoeff() <= params.step_tolerance ||
        (project_to_box(result.x - result.gradient, lower, upper) - result.x).isZero(0.0)) {
      result.status = BoundedGaussNewtonStatus::Stationary;
      return result;
    }
    if (params.decrease_tolerance > 0.0) {
      const VecX s = project_to_box(result.x + newton, lower, upper) - result.x;
      if (model_decrease(result.gradient, result.model, s) <= params.decrease_tolerance * result.value) {
        result.status = BoundedGaussNewtonStatus::Settled;
        return result;
      }
    }
    if (mu > params.max_damping) {
      result.status = BoundedGaussNewtonStatus::NoDecrease;
      return result;
    }
    if (result.evaluations >= params.max_evaluations) {
      result.status = BoundedGaussNewtonStatus::EvaluationBudget;
      return result;
    }
    VecX step = damped_step(result.gradient, result.model, held, mu);
    const double largest = step.cwiseAbs().maxCoeff();
    double limit = params.max_step > 0.0 ? params.max_step : std::numeric_limits<double>::infinity();
    if (result.iterations == 0 && params.first_step > 0.0) limit = std::min(limit, params.first_step);
    if (largest > limit) step *= limit / largest;
    const VecX trial = project_to_box(result.x + step, lower, upper);
    const VecX s = trial - result.x;
    const double predicted = model_decrease(result.gradient, result.model, s);
    const double value = f(trial, gradient, model);
    ++result.evaluations;
    if (std::isfinite(value) && value < result.value && gradient.allFinite() && model.allFinite()) {
      const double ratio = predicted > 0.0 ? (result.value - value) / predicted : 1.0;
      mu *= std::max(kFastestShrink, 1.0 - std::pow(2.0 * ratio - 1.0, 3));
      growth = 2.0;
      result.x = trial;
      result.value = value;
      result.gradient = gradient;
      result.model = model;
      ++result.iterations;
    } else {
      mu = std::max(mu, params.initial_damping > 0.0 ? params.initial_damping : 1e-3) * growth;
      growth *= 2.0;
    }
  }
}

}  // namespace fnopt
