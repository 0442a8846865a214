#include <fnopt/adjoint/bounded_lbfgs.hpp>

#include <cmath>
#include <deque>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

VecX project(const VecX& x, const VecX& lower, const VecX& upper) { return x.cwiseMax(lower).cwiseMin(upper); }

double projected_gradient_norm(const VecX& x, const VecX& g, const VecX& lower, const VecX& upper) {
  return (project(x - g, lower, upper) - x).cwiseAbs().maxCoeff();
}

// Variables held at a bound: at it, with the gradient pushing out of the box.
std::vector<char> active_set(const VecX& x, const VecX& g, const VecX& lower, const VecX& upper) {
  std::vector<char> active(x.size(), 0);
  for (Eigen::Index i = 0; i < x.size(); ++i)
    active[i] = (x[i] <= lower[i] && g[i] > 0.0) || (x[i] >= upper[i] && g[i] < 0.0);
  return active;
}

struct Pair {
  VecX s, y;
  double rho;
};

}  // namespace

const char* to_string(BoundedLbfgsStatus status) {
  switch (status) {
    case BoundedLbfgsStatus::Converged:
      return "converged";
    case BoundedLbfgsStatus::IterationBudget:
      return "iteration-budget";
    case BoundedLbfgsStatus::EvaluationBudget:
      return "evaluation-budget";
    case BoundedLbfgsStatus::LineSearchFailed:
      return "line-search-failed";
    case BoundedLbfgsStatus::NonFinite:
      return "non-finite";
  }
  return "unknown";
}

void BoundedLbfgsParams::validate() const {
  require(history >= 1, "history", "must be at least 1");
  require(max_iterations >= 1, "max_iterations", "must be at least 1");
  require(std::isfinite(gradient_tolerance) && gradient_tolerance >= 0.0, "gradient_tolerance", "must be zero or more");
  require(!std::isnan(value_tolerance), "value_tolerance", "must be a number");
  require(armijo > 0.0 && armijo < 1.0, "armijo", "must be in (0, 1)");
  require(max_backtracks >= 1, "max_backtracks", "must be at least 1");
  require(max_evaluations >= 0, "max_evaluations", "must be zero (no limit) or more");
  require(std::isfinite(first_step) && first_step >= 0.0, "first_step", "must be zero (unscaled) or more");
  require(std::isfinite(relative_decrease) && relative_decrease >= 0.0, "relative_decrease",
          "must be zero (never) or more");
}

BoundedLbfgsResult minimize_in_box(const BoundedObjective& f, const VecX& x0, const VecX& lower, const VecX& upper,
                                   const BoundedLbfgsParams& params) {
  params.validate();
  require(lower.size() == x0.size() && upper.size() == x0.size(), "bounds",
          "expected " + std::to_string(x0.size()) + " lower and upper bounds");
  require((lower.array() <= upper.array()).all(), "bounds", "a lower bound is above its upper bound");

  BoundedLbfgsResult result;
  result.x = project(x0, lower, upper);
  VecX g(x0.size());
  result.value = f(result.x, g);
  ++result.evaluations;
  if (!std::isfinite(result.value) || !g.allFinite()) {
    result.status = BoundedLbfgsStatus::NonFinite;
    return result;
  }
  const double first_norm = projected_gradient_norm(result.x, g, lower, upper);
  std::deque<Pair> pairs;
  VecX trial_g(x0.size());
  for (;;) {
    const double norm = projected_gradient_norm(result.x, g, lower, upper);
    if (norm <= params.gradient_tolerance * first_norm || result.value <= params.value_tolerance) {
      result.status = BoundedLbfgsStatus::Converged;
      return result;
    }
    if (result.iterations >= params.max_iterations) {
      result.status = BoundedLbfgsStatus::IterationBudget;
      return result;
    }

    const std::vector<char> active = active_set(result.x, g, lower, upper);
    VecX q = g;
    for (Eigen::Index i = 0; i < q.size(); ++i)
      if (active[i]) q[i] = 0.0;
    const VecX free_gradient = q;
    std::vector<double> alpha(pairs.size());
    for (std::size_t k = pairs.size(); k-- > 0;) {
      alpha[k] = pairs[k].rho * pairs[k].s.dot(q);
      q -= alpha[k] * pairs[k].y;
    }
    if (!pairs.empty()) q *= pairs.back().s.dot(pairs.back().y) / pairs.back().y.squaredNorm();
    for (std::size_t k = 0; k < pairs.size(); ++k) q += (alpha[k] - pairs[k].rho * pairs[k].y.dot(q)) * pairs[k].s;
    VecX direction = -q;
    for (Eigen::Index i = 0; i < direction.size(); ++i)
      if (active[i]) direction[i] = 0.0;
    if (!(direction.dot(free_gradient) < 0.0)) direction = -free_gradient;
    if (pairs.empty() && params.first_step > 0.0 && direction.cwiseAbs().maxCoeff() > 0.0)
      direction *= params.first_step / direction.cwiseAbs().maxCoeff();

    double step = 1.0;
    bool accepted = false;
    VecX trial;
    double trial_value = 0.0;
    for (int b = 0; b < params.max_backtracks; ++b, step *= 0.5) {
      if (params.max_evaluations > 0 && result.evaluations >= params.max_evaluations) {
        result.status = BoundedLbfgsStatus::EvaluationBudget;
        return result;
      }
      trial = project(result.x + step * direction, lower, upper);
      trial_value = f(trial, trial_g);
      ++result.evaluations;
      if (std::isfinite(trial_value) && trial_g.allFinite() &&
          trial_value <= result.value + params.armijo * g.dot(trial - result.x)) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      result.status = BoundedLbfgsStatus::LineSearchFailed;
      return result;
    }
    Pair pair{trial - result.x, trial_g - g, 0.0};
    const double curvature = pair.s.dot(pair.y);
    if (curvature > 1e-10 * pair.s.norm() * pair.y.norm()) {
      pair.rho = 1.0 / curvature;
      pairs.push_back(std::move(pair));
      if (static_cast<int>(pairs.size()) > params.history) pairs.pop_front();
    }
    const bool stalled = result.value - trial_value <= params.relative_decrease * std::abs(result.value);
    result.x = trial;
    result.value = trial_value;
    g = trial_g;
    ++result.iterations;
    if (params.relative_decrease > 0.0 && stalled) {
      result.status = BoundedLbfgsStatus::Converged;
      return result;
    }
  }
}

}  // namespace fnopt
