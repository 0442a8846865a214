#pragma once
// Backtracking line search (Armijo; Nocedal & Wright 2006, Alg. 3.1), shared by the methods
// whose direction already has a good length: Newton and the prefactored quasi-Newton method.
//
// From a with value L(a) and slope = g.d < 0, trials t = 1, shrink, shrink^2, ... until
//   L(a + t d) < L(a)  and  L(a + t d) <= L(a) + armijo t slope.
// Armijo's test must also see a strict decrease, so that a step too small to change L is never
// taken as progress. Close to the minimum L changes by less than its rounding error (L sums
// terms larger than itself); there a trial that halves ||g|| is accepted instead ("flat"): at
// the gradient's own rounding floor, noise lowers ||g|| by a hair at every step, and accepting
// that would let a solve wander until its budget.
#include <cmath>
#include <optional>
#include <string>

#include "optimizer/solve_status.hpp"
#include "util/error.hpp"
#include "util/types.hpp"

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
// Problem: anything with double value_gradient(const VecX& a, VecX& gradient).
template <class Problem>
std::optional<SolveStatus> backtracking_line_search(Problem& problem, VecX& a, double& value, VecX& gradient,
                                                    const VecX& direction, const LineSearchStart& start,
                                                    const BacktrackingParams& params, LineSearchScratch& scratch) {
  double step = 1.0;
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

}  // namespace fnopt
