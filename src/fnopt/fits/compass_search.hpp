#pragma once
// Minimisation of a function in a box, l <= x <= u, by compass search (Kolda, Lewis & Torczon
// 2003, "Optimization by direct search", §3): poll x +- s e_i coordinate by coordinate, move to
// the first point that lowers f, halve s after a poll without improvement, stop once s is below
// final_step. Derivative-free: the baseline that the adjoint's fits are measured against
// (docs/design.md §15), and `fnopt fit-material --method compass` on e_CD, which has no gradient.
// Deterministic; a non-finite value (a rollout that diverged) never counts as an improvement.
#include <functional>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct CompassSearchParams {
  double initial_step = 1.0;  // first poll step, in the variables' units
  double final_step = 0.02;   // stop once the step is below this
  int max_evaluations = 120;  // calls of f at most (the start included)

  void validate() const;  // throws Error naming the field
};

struct CompassSearchResult {
  VecX x;               // the best point evaluated
  double value = 0.0;   // f there
  int evaluations = 0;  // calls of f
  double final_step = 0.0;
  bool converged = false;  // the step fell below final_step (else the evaluation budget ended it)
};

using CompassObjective = std::function<double(const VecX& x)>;

// Minimises f from x0 (projected into the box first). Points already evaluated, on the search's
// lattice of quarter final steps, are not evaluated again: a poll that returns to a point costs
// nothing. Throws Error("bounds", ...) for bounds of the wrong size or with l > u somewhere.
CompassSearchResult minimize_by_compass(const CompassObjective& f, const VecX& x0, const VecX& lower, const VecX& upper,
                                        const CompassSearchParams& params = {});

}  // namespace fnopt
