#include "baselines/lbfgs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "util/error.hpp"

namespace fnopt {
namespace {

// One line-search trial: the step t, phi(t) = L(x + t d) and phi'(t) = g(x + t d).d.
struct Trial {
  double step = 0.0;
  double value = 0.0;
  double slope = 0.0;
};

// Minimiser of the cubic through two trials (Nocedal & Wright eq. 3.59), kept at least 10 % of
// the interval away from both ends; bisection where the cubic has no usable minimiser.
double cubic_step(const Trial& a, const Trial& b) {
  const double lo = std::min(a.step, b.step), hi = std::max(a.step, b.step), width = hi - lo;
  double t = std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(a.value) && std::isfinite(b.value) && std::isfinite(a.slope) && std::isfinite(b.slope)) {
    const double d1 = a.slope + b.slope - 3.0 * (a.value - b.value) / (a.step - b.step);
    const double radicand = d1 * d1 - a.slope * b.slope;
    if (radicand >= 0.0) {
      const double d2 = std::copysign(std::sqrt(radicand), b.step - a.step);
      t = b.step - (b.step - a.step) * (b.slope + d2 - d1) / (b.slope - a.slope + 2.0 * d2);
    }
  }
  if (!std::isfinite(t)) return 0.5 * (lo + hi);
  return std::clamp(t, lo + 0.1 * width, hi - 0.1 * width);
}

}  // namespace

void LbfgsParams::validate() const {
  require(history >= 1 && history <= 1000, "lbfgs.history", "must lie in [1, 1000]");
  require(wolfe_c1 > 0.0 && wolfe_c1 < 0.5, "lbfgs.wolfe_c1", "must lie in (0, 0.5)");
  require(wolfe_c2 > wolfe_c1 && wolfe_c2 < 1.0, "lbfgs.wolfe_c2", "must lie in (wolfe_c1, 1)");
  require(max_line_search_evaluations >= 1, "lbfgs.max_line_search_evaluations", "must be positive");
}

LbfgsOptimizer::LbfgsOptimizer(LbfgsParams params) : params_(validated(params)), history_(params_.history) {}

std::string LbfgsOptimizer::settings() const {
  std::ostringstream out;
  out << name() << ": history=" << params_.history << " (mass metric, H0 = s.y/(y.P^-1 y) P^-1)";
  if (params_.line_search)
    out << " strong Wolfe line search c1=" << params_.wolfe_c1 << " c2=" << params_.wolfe_c2
        << " max_evaluations=" << params_.max_line_search_evaluations;
  else
    out << " fixed step 1, no line search";
  return out.str();
}

void LbfgsOptimizer::begin(SmoothProblem&, const VecX&, double, const VecX&) { history_.clear(); }

void LbfgsOptimizer::remember(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new,
                              const VecX& inverse_metric) {
  // Keep only pairs of clearly positive curvature (cosine in the metric above 1e-10).
  const bool stored = history_.push(x_old, g_old, x_new, g_new, [&](const CurvaturePair& pair, double sy) {
    const double s_norm2 = pair.s.cwiseQuotient(inverse_metric).dot(pair.s);  // s.P s
    const double y_norm2 = pair.y.cwiseProduct(inverse_metric).dot(pair.y);   // y.P^-1 y
    return std::isfinite(sy) && sy > 1e-10 * std::sqrt(s_norm2 * y_norm2);
  });
  if (!stored) ++skipped_pairs_;
}

double LbfgsOptimizer::compute_direction(SmoothProblem& problem, const VecX& gradient) {
  const VecX& inverse_metric = problem.inverse_metric();
  if (history_.size() > 0) {
    const CurvaturePair& newest = history_.newest();
    const double gamma = 1.0 / (newest.rho * newest.y.cwiseProduct(inverse_metric).dot(newest.y));
    h0_ = gamma * inverse_metric;
    lbfgs_two_loop(history_.oldest_first(), [&](VecX& q) { q.array() *= h0_.array(); }, gradient, direction_, alphas_);
    const double slope = gradient.dot(direction_);
    if (std::isfinite(slope) && slope < 0.0) return 1.0;
    history_.clear();  // not a descent direction (rounding): restart from the metric gradient step
  }
  direction_ = -inverse_metric.cwiseProduct(gradient);
  if (params_.line_search) return 1.0;
  const double l1 = direction_.lpNorm<1>();
  return l1 > 1.0 ? 1.0 / l1 : 1.0;
}

bool LbfgsOptimizer::line_search(SmoothProblem& problem, VecX& x, double& value, VecX& gradient,
                                 double first_step) {
  const double phi0 = value, slope0 = gradient.dot(direction_);
  // Below this, L(x + t d) - L(x) is rounding: test the slope instead of the decrease.
  const double rounding = 1e-12 * std::abs(phi0);
  double best_value = phi0;
  bool have_best = false;
  int evaluations = 0;
  auto evaluate = [&](double t) {
    ++evaluations;
    ++evaluations_;
    trial_x_ = x + t * direction_;
    Trial trial{t, problem.value_gradient(trial_x_, trial_g_), 0.0};
    trial.slope = trial_g_.dot(direction_);
    if (!std::isfinite(trial.value) || !std::isfinite(trial.slope)) {
      trial.value = std::numeric_limits<double>::infinity();
      trial.slope = std::numeric_limits<double>::quiet_NaN();
    } else if (trial.value < best_value) {
      best_value = trial.value;
      best_x_ = trial_x_;
      best_g_ = trial_g_;
      have_best = true;
    }
    return trial;
  };
  auto sufficient = [&](const Trial& t) {
    return (t.value <= phi0 + params_.wolfe_c1 * t.step * slope0 && t.value < phi0) ||
           std::abs(t.value - phi0) <= rounding;
  };
  auto curvature = [&](const Trial& t) { return std::abs(t.slope) <= -params_.wolfe_c2 * slope0; };
  auto accept = [&](const Trial& t) {
    x.swap(trial_x_);
    gradient.swap(trial_g_);
    value = t.value;
    return true;
  };
  auto zoom = [&](Trial lo, Trial hi) {
    while (evaluations < params_.max_line_search_evaluations) {
      const Trial t = evaluate(cubic_step(lo, hi));
      if (!sufficient(t) || t.value >= lo.value) {
        hi = t;
      } else {
        if (curvature(t)) return accept(t);
        if (t.slope * (hi.step - lo.step) >= 0.0) hi = lo;
        lo = t;
      }
      if (std::abs(hi.step - lo.step) <= 1e-12 * std::max(lo.step, hi.step)) break;
    }
    return false;
  };

  Trial previous{0.0, phi0, slope0};
  double step = first_step;
  bool done = false;
  for (int i = 0; !done && evaluations < params_.max_line_search_evaluations; ++i) {
    const Trial t = evaluate(step);
    if (!sufficient(t) || (i > 0 && t.value >= previous.value)) {
      done = zoom(previous, t);
      break;
    }
    if (curvature(t)) return accept(t);
    if (t.slope >= 0.0) {
      done = zoom(t, previous);
      break;
    }
    previous = t;
    step *= 4.0;
  }
  if (done) return true;
  if (!have_best) return false;
  // No Wolfe point within the evaluation budget: take the lowest trial.
  x = best_x_;
  gradient = best_g_;
  value = best_value;
  return true;
}

std::optional<SolveStatus> LbfgsOptimizer::step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) {
  const double first_step = compute_direction(problem, gradient);
  x_old_ = x;
  g_old_ = gradient;
  if (params_.line_search) {
    if (!line_search(problem, x, value, gradient, first_step)) return SolveStatus::LineSearchFailed;
  } else {
    x.noalias() += first_step * direction_;
    value = problem.value_gradient(x, gradient);
    if (!std::isfinite(value) || !gradient.allFinite()) return SolveStatus::NonFinite;
  }
  remember(x_old_, g_old_, x, gradient, problem.inverse_metric());
  return std::nullopt;
}

}  // namespace fnopt
