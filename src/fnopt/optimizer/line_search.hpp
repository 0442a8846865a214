#pragma once
// The line searches of the inner optimizers (docs/design.md §6), one module for all:
//  - backtracking (Armijo), for the methods whose direction already has a good length: Newton
//    and the prefactored quasi-Newton method;
//  - strong Wolfe (bracketing and zoom), for L-BFGS, whose curvature pairs need the curvature
//    condition (s.y > 0 keeps its inverse-Hessian model positive definite), which backtracking
//    does not give.
// The learned optimizer does not search a line: its rule takes one secant or subspace trial per
// iteration (learned/proposal_rule.hpp), a fixed cost that its training assumes.
//
// Backtracking (Nocedal & Wright 2006, Alg. 3.1):
// From a with value L(a) and slope = g.d < 0, trials t = 1, shrink, shrink^2, ... until
//   L(a + t d) < L(a)  and  L(a + t d) <= L(a) + armijo t slope.
// Armijo's test must also see a strict decrease, so that a step too small to change L is never
// taken as progress. Close to the minimum L changes by less than its rounding error (L sums
// terms larger than itself); there a trial that halves ||g|| is accepted instead ("flat"): at
// the gradient's own rounding floor, noise lowers ||g|| by a hair at every step, and accepting
// that would let a solve wander until its budget.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <fnopt/optimizer/solve_status.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

struct BacktrackingParams {
  double armijo = 1e-4;  // sufficient-decrease constant c1
  double shrink = 0.5;   // step factor per rejected trial
  int max_trials = 40;   // trials per line search

  // Throws Error("<owner>.armijo: ...") naming the bad parameter.
  void validate(const std::string& owner) const {
    require(armijo > 0.0 && armijo < 0.5, owner + ".armijo", "must lie in (0, 0.5)");
    require(shrink > 0.0 && shrink < 1.0, owner + ".backtrack", "must lie in (0, 1)");
    require(max_trials > 0, owner + ".max_backtracks", "must be positive");
  }
};

// Where the line search starts: L(a), the slope g.d along the direction, ||g||, and the size
// of L's rounding error below which a change of L is not a decrease.
struct LineSearchStart {
  double value = 0.0;
  double slope = 0.0;
  double gradient_norm = 0.0;
  double rounding = 0.0;
};

// Buffers of the trials, kept by the caller so that a line search allocates nothing.
struct LineSearchScratch {
  VecX trial, trial_gradient;
};

// Moves a, value and gradient to the accepted trial and returns nothing; otherwise leaves them
// and returns PrecisionLimit where no step could lower L by more than its rounding error
// (-slope below it: a minimiser to the precision of L), LineSearchFailed elsewhere.
// A trial of infinite or NaN value (inside an obstacle, docs/design.md §14) is rejected; the first
// trial is `first_step`, below 1 where the caller knows that a full step enters an obstacle.
// Problem: anything with double value_gradient(const VecX& a, VecX& gradient).
template <class Problem>
std::optional<SolveStatus> backtracking_line_search(Problem& problem, VecX& a, double& value, VecX& gradient,
                                                    const VecX& direction, const LineSearchStart& start,
                                                    const BacktrackingParams& params, LineSearchScratch& scratch,
                                                    double first_step = 1.0) {
  double step = first_step;
  for (int trial = 0; trial < params.max_trials; ++trial, step *= params.shrink) {
    scratch.trial = a + step * direction;
    const double trial_value = problem.value_gradient(scratch.trial, scratch.trial_gradient);
    if (!std::isfinite(trial_value)) continue;
    const bool armijo = trial_value < start.value && trial_value <= start.value + params.armijo * step * start.slope;
    const bool flat = !armijo && std::abs(trial_value - start.value) <= start.rounding &&
                      scratch.trial_gradient.norm() < 0.5 * start.gradient_norm;
    if (armijo || flat) {
      a.swap(scratch.trial);
      gradient.swap(scratch.trial_gradient);
      value = trial_value;
      return std::nullopt;
    }
  }
  return -start.slope <= start.rounding ? SolveStatus::PrecisionLimit : SolveStatus::LineSearchFailed;
}

// ---- Strong Wolfe ------------------------------------------------------------------------------
// Nocedal & Wright, Algorithms 3.5 (bracketing; trial steps grow x4) and 3.6 (zoom by safeguarded
// cubic interpolation), on phi(t) = L(a + t d):
//   sufficient decrease  phi(t) <= phi(0) + c1 t phi'(0) and phi(t) < phi(0),
//   curvature            |phi'(t)| <= c2 |phi'(0)|.
// Where L can no longer resolve a decrease (|phi(t) - phi(0)| below 1e-12 |phi(0)|, close to the
// minimum) the decrease test passes and the curvature condition decides. With no Wolfe point
// within the evaluation budget, the lowest finite trial is taken.

struct WolfeParams {
  double c1 = 1e-4;          // sufficient decrease
  double c2 = 0.9;           // curvature condition
  int max_evaluations = 20;  // trials per line search

  // Throws Error("<owner>.wolfe_c1: ...") naming the bad parameter.
  void validate(const std::string& owner) const {
    require(c1 > 0.0 && c1 < 0.5, owner + ".wolfe_c1", "must lie in (0, 0.5)");
    require(c2 > c1 && c2 < 1.0, owner + ".wolfe_c2", "must lie in (wolfe_c1, 1)");
    require(max_evaluations >= 1, owner + ".max_line_search_evaluations", "must be positive");
  }
};

// One trial: the step t, phi(t) and phi'(t) = g(a + t d).d.
struct WolfeTrial {
  double step = 0.0;
  double value = 0.0;
  double slope = 0.0;
};

// Minimiser of the cubic through two trials (Nocedal & Wright eq. 3.59), kept at least 10 % of
// the interval away from both ends; bisection where the cubic has no usable minimiser.
inline double cubic_step(const WolfeTrial& a, const WolfeTrial& b) {
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

// Buffers of the trials and of the lowest one, kept by the caller: no allocation per search.
struct WolfeScratch {
  VecX trial, trial_gradient, best, best_gradient;
};

// From a (value L(a), gradient g) along the descent direction d, first trial step `first_step`.
// A trial of infinite or NaN value or slope (inside an obstacle, docs/design.md §14) is rejected:
// it counts as too long, so the search zooms below it.
// On success moves a, value and gradient to the accepted point and returns true; returns false
// where no trial was finite and lower. `evaluations` counts the gradient evaluations made.
template <class Problem>
bool wolfe_line_search(Problem& problem, VecX& a, double& value, VecX& gradient, const VecX& direction,
                       double first_step, const WolfeParams& params, WolfeScratch& scratch, int& evaluations) {
  const double phi0 = value, slope0 = gradient.dot(direction);
  const double rounding = 1e-12 * std::abs(phi0);
  double best_value = phi0;
  bool have_best = false;
  evaluations = 0;
  auto evaluate = [&](double t) {
    ++evaluations;
    scratch.trial = a + t * direction;
    WolfeTrial trial{t, problem.value_gradient(scratch.trial, scratch.trial_gradient), 0.0};
    trial.slope = scratch.trial_gradient.dot(direction);
    if (!std::isfinite(trial.value) || !std::isfinite(trial.slope)) {
      trial.value = std::numeric_limits<double>::infinity();
      trial.slope = std::numeric_limits<double>::quiet_NaN();
    } else if (trial.value < best_value) {
      best_value = trial.value;
      scratch.best = scratch.trial;
      scratch.best_gradient = scratch.trial_gradient;
      have_best = true;
    }
    return trial;
  };
  auto sufficient = [&](const WolfeTrial& t) {
    return (t.value <= phi0 + params.c1 * t.step * slope0 && t.value < phi0) || std::abs(t.value - phi0) <= rounding;
  };
  auto curvature = [&](const WolfeTrial& t) { return std::abs(t.slope) <= -params.c2 * slope0; };
  auto accept = [&](const WolfeTrial& t) {
    a.swap(scratch.trial);
    gradient.swap(scratch.trial_gradient);
    value = t.value;
    return true;
  };
  auto zoom = [&](WolfeTrial lo, WolfeTrial hi) {
    while (evaluations < params.max_evaluations) {
      const WolfeTrial t = evaluate(cubic_step(lo, hi));
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

  WolfeTrial previous{0.0, phi0, slope0};
  double step = first_step;
  bool done = false;
  for (int i = 0; !done && evaluations < params.max_evaluations; ++i) {
    const WolfeTrial t = evaluate(step);
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
  a = scratch.best;
  gradient = scratch.best_gradient;
  value = best_value;
  return true;
}

}  // namespace fnopt
