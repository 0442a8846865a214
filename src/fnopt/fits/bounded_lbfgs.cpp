#include <fnopt/fits/bounded_lbfgs.hpp>

#include <cmath>
#include <optional>

#include <fnopt/baselines/curvature_history.hpp>
#include <fnopt/fits/box_bounds.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double projected_gradient_norm(const VecX& x, const VecX& g, const VecX& lower, const VecX& upper) {
  return (project_to_box(x - g, lower, upper) - x).cwiseAbs().maxCoeff();
}

// The search direction at x: the two-loop recursion on the free variables (H0 = gamma I, gamma
// from the newest pair), -g where that is not a descent direction, scaled to first_step before
// the first pair.
VecX search_direction(const VecX& x, const VecX& g, const VecX& lower, const VecX& upper, CurvatureHistory& history,
                      const BoundedLbfgsParams& params, std::vector<double>& alphas) {
  const std::vector<char> active = held_at_bounds(x, g, lower, upper);
  VecX free_gradient = g;
  for (Eigen::Index i = 0; i < g.size(); ++i)
    if (active[i]) free_gradient[i] = 0.0;
  VecX direction;
  const auto scale_by_newest = [&history](VecX& q) {
    if (history.size() == 0) return;
    const CurvaturePair& newest = history.newest();
    q *= newest.s.dot(newest.y) / newest.y.squaredNorm();
  };
  lbfgs_two_loop(history.oldest_first(), scale_by_newest, free_gradient, direction, alphas);
  for (Eigen::Index i = 0; i < direction.size(); ++i)
    if (active[i]) direction[i] = 0.0;
  if (!(direction.dot(free_gradient) < 0.0)) direction = -free_gradient;
  if (history.size() == 0 && params.first_step > 0.0 && direction.cwiseAbs().maxCoeff() > 0.0)
    direction *= params.first_step / direction.cwiseAbs().maxCoeff();
  return direction;
}

// The projected backtracking line search from result.x along `direction`: the first of
// alpha = 1, 1/2, ... whose point satisfies Armijo's condition, written to trial and trial_g.
// Returns nothing when a step is accepted, else the status that ends the minimisation.
std::optional<BoundedLbfgsStatus> backtrack(const BoundedObjective& f, const BoundedLbfgsResult& result, const VecX& g,
                             const VecX& direction, const VecX& lower, const VecX& upper,
                             const BoundedLbfgsParams& params, int& evaluations, VecX& trial, VecX& trial_g,
                             double& trial_value) {
  double step = 1.0;
  for (int b = 0; b < params.max_backtracks; ++b, step *= 0.5) {
    if (params.max_evaluations > 0 && evaluations >= params.max_evaluations) return BoundedLbfgsStatus::EvaluationBudget;
    trial = project_to_box(result.x + step * direction, lower, upper);
    trial_value = f(trial, trial_g);
    ++evaluations;
    if (std::isfinite(trial_value) && trial_g.allFinite() &&
        trial_value <= result.value + params.armijo * g.dot(trial - result.x))
      return std::nullopt;
  }
  return BoundedLbfgsStatus::LineSearchFailed;
}

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
  check_box(x0, lower, upper);

  BoundedLbfgsResult result;
  result.x = project_to_box(x0, lower, upper);
  VecX g(x0.size());
  result.value = f(result.x, g);
  ++result.evaluations;
  if (!std::isfinite(result.value) || !g.allFinite()) {
    result.status = BoundedLbfgsStatus::NonFinite;
    return result;
  }
  const double first_norm = projected_gradient_norm(result.x, g, lower, upper);
  CurvatureHistory history(params.history);
  std::vector<double> alphas;
  VecX trial, trial_g(x0.size());
  for (;;) {
    if (projected_gradient_norm(result.x, g, lower, upper) <= params.gradient_tolerance * first_norm ||
        result.value <= params.value_tolerance) {
      result.status = BoundedLbfgsStatus::Converged;
      return result;
    }
    if (result.iterations >= params.max_iterations) {
      result.status = BoundedLbfgsStatus::IterationBudget;
      return result;
    }
    const VecX direction = search_direction(result.x, g, lower, upper, history, params, alphas);
    double trial_value = 0.0;
    const std::optional<BoundedLbfgsStatus> stop = backtrack(f, result, g, direction, lower, upper, params,
                                                             result.evaluations, trial, trial_g, trial_value);
    if (stop) {
      result.status = *stop;
      return result;
    }
    history.push(result.x, g, trial, trial_g, [](const CurvaturePair& pair, double sy) {
      return clearly_positive_curvature(sy, pair.s.norm() * pair.y.norm());
    });
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
