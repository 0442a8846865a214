#pragma once
// Minimisation of a smooth function in a box, l <= x <= u, by projected L-BFGS (in the spirit of
// L-BFGS-B, Byrd, Lu, Nocedal & Zhu 1995, without its generalised Cauchy point): for the few
// variables of a material fit (docs/design.md §15), on any callable objective with its gradient.
//
// Per iteration: the variables at a bound whose gradient points out of the box are held (the
// active set); on the others the two-loop recursion over the last `history` pairs (s, y) gives
// d = -H g (baselines/curvature_history.hpp's, shared with lbfgs and pqn; initial inverse Hessian
// gamma I, gamma = s.y / y.y of the newest pair; -g before the first, optionally scaled to first_step), replaced by -g where it is not a descent direction;
// then a projected backtracking line search x(alpha) = P(x + alpha d), alpha = 1, 1/2, ..., accepting the first with
//   f(x(alpha)) <= f(x) + c1 g.(x(alpha) - x).
// A pair is kept only if s.y > 1e-10 |s| |y| (so H stays positive definite). The stop: the
// projected gradient ||P(x - g) - x||_inf is at most `gradient_tolerance` times its first value.
#include <functional>
#include <limits>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct BoundedLbfgsParams {
  int history = 6;  // pairs (s, y) kept
  int max_iterations = 50;
  double gradient_tolerance = 1e-8;  // relative to the first projected gradient
  // Also stop once f <= this.
  double value_tolerance = -std::numeric_limits<double>::infinity();
  double armijo = 1e-4;     // c1
  int max_backtracks = 30;  // halvings of alpha before line-search-failed
  int max_evaluations = 0;  // calls of the objective at most (0: no limit)
  // Also stop once an accepted step lowers f by at most this fraction of |f| (0: never): on a loss
  // that is rough at the solver's precision the iterations can go on long past any useful gain.
  double relative_decrease = 0.0;
  // Before the first pair, d = -g scaled so that no variable moves more than this at alpha = 1
  // (the gradient's scale says nothing about the step's; 0: d = -g as it is).
  double first_step = 0.0;

  void validate() const;  // throws Error naming the field
};

enum class BoundedLbfgsStatus {
  Converged,         // the projected gradient, the value or a step's relative decrease is below its tolerance
  IterationBudget,   // max_iterations used
  EvaluationBudget,  // max_evaluations used (x: the best point the iterations accepted)
  LineSearchFailed,  // no step along d decreased f enough
  NonFinite,         // f or its gradient is not finite at the start
};
const char* to_string(BoundedLbfgsStatus status);

struct BoundedLbfgsResult {
  VecX x;
  double value = 0.0;
  BoundedLbfgsStatus status = BoundedLbfgsStatus::IterationBudget;
  int iterations = 0;
  int evaluations = 0;  // calls of the objective
};

// f(x), writing its gradient to `gradient`.
using BoundedObjective = std::function<double(const VecX& x, VecX& gradient)>;

// Minimises f from x0 (projected into the box first). Throws Error("bounds", ...) for bounds of the
// wrong size or with l > u somewhere.
BoundedLbfgsResult minimize_in_box(const BoundedObjective& f, const VecX& x0, const VecX& lower, const VecX& upper,
                                   const BoundedLbfgsParams& params = {});

}  // namespace fnopt
