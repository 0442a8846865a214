#include <fnopt/baselines/lbfgs.hpp>

#include <cmath>
#include <sstream>

#include <fnopt/optimizer/line_search.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
void LbfgsParams::validate() const {
  require(history >= 1 && history <= 1000, "lbfgs.history", "must lie in [1, 1000]");
  wolfe.validate("lbfgs");
}

LbfgsOptimizer::LbfgsOptimizer(LbfgsParams params) : params_(validated(params)), history_(params_.history) {}

std::string LbfgsOptimizer::settings() const {
  std::ostringstream out;
  out << name() << ": history=" << params_.history << " (mass metric, H0 = s.y/(y.P^-1 y) P^-1)";
  if (params_.line_search)
    out << " strong Wolfe line search c1=" << params_.wolfe.c1 << " c2=" << params_.wolfe.c2
        << " max_evaluations=" << params_.wolfe.max_evaluations;
  else
    out << " fixed step 1, no line search";
  return out.str();
}

void LbfgsOptimizer::begin(SmoothProblem&, const VecX&, double, const VecX&) { history_.clear(); }

void LbfgsOptimizer::remember(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new,
                              const VecX& inverse_metric) {
  // Keep only pairs of clearly positive curvature, the cosine in the metric.
  const bool stored = history_.push(x_old, g_old, x_new, g_new, [&](const CurvaturePair& pair, double sy) {
    const double s_norm2 = pair.s.cwiseQuotient(inverse_metric).dot(pair.s);  // s.P s
    const double y_norm2 = pair.y.cwiseProduct(inverse_metric).dot(pair.y);   // y.P^-1 y
    return clearly_positive_curvature(sy, std::sqrt(s_norm2 * y_norm2));
  });
  if (!stored) ++skipped_pairs_;
}

double LbfgsOptimizer::compute_direction(SmoothProblem& problem, const VecX& gradient) {
  const VecX& inverse_metric = problem.inverse_metric();
  if (history_.size() > 0) {
    const CurvaturePair& newest = history_.newest();
    const double gamma = 1.0 / (newest.rho * newest.y.cwiseProduct(inverse_metric).dot(newest.y));
    h0_ = gamma * inverse_metric;
    lbfgs_two_loop(
        history_.oldest_first(), [&](VecX& q) { q.array() *= h0_.array(); }, gradient, direction_, alphas_);
    const double slope = gradient.dot(direction_);
    if (std::isfinite(slope) && slope < 0.0) return 1.0;
    history_.clear();  // not a descent direction (rounding): restart from the metric gradient step
  }
  direction_ = -inverse_metric.cwiseProduct(gradient);
  if (params_.line_search) return 1.0;
  const double l1 = direction_.lpNorm<1>();
  return l1 > 1.0 ? 1.0 / l1 : 1.0;
}

std::optional<SolveStatus> LbfgsOptimizer::step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) {
  const double first_step = compute_direction(problem, gradient);
  x_old_ = x;
  g_old_ = gradient;
  if (params_.line_search) {
    const double feasible_first_step = problem.feasible_step(x, direction_, first_step);
    int evaluations = 0;
    const bool moved = wolfe_line_search(problem, x, value, gradient, direction_, feasible_first_step, params_.wolfe,
                                         line_search_, evaluations);
    evaluations_ += evaluations;
    if (!moved) return SolveStatus::LineSearchFailed;
  } else {
    x.noalias() += first_step * direction_;
    value = problem.value_gradient(x, gradient);
    if (!std::isfinite(value) || !gradient.allFinite()) return SolveStatus::NonFinite;
  }
  remember(x_old_, g_old_, x, gradient, problem.inverse_metric());
  return std::nullopt;
}

}  // namespace fnopt
