#pragma once
// The energy where fnopt-ss ends after a proposal, as a function of that proposal, for a
// meta-training loss that scores what inference keeps rather than the raw proposal.
//
// With the kept directions S_old (and their gradient differences Y_old), a proposal p made at a
// joins them as s_k = p, y_k = g(a + p) - g(a), and the rule moves to a + S c with
//   c = -M^+ S^T g(a),   M = (S^T Y + Y^T S) / 2                    (secant_subspace.hpp)
// when that lowers L below L(a + p). The derivative of L(a + S c) with respect to p, with
// g' = g(a + S c), w = M^+ S^T g' and u = (c_k S w + w_k S c) / 2, is
//   dL/dp = c_k g' - w_k g(a) - (w_k Y c + c_k Y w) / 2 - H(a + p) u,
// from dc = -M^+ (dM c + dS^T g) and dy = H(a + p) dp. The Hessian-vector product H u is a
// central difference of the analytic gradient (two gradients), so the energy is still written
// once, in cloth/.
#include <fnopt/optimizer/secant_subspace.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

struct SubspaceStepOutcome {
  double value = 0.0;  // L where the rule ends: a + S c if that is lower than L(a + p), else a + p
  VecX gradient;       // d value / d p (masked, acceleration units)
  bool taken = false;  // whether the rule ends at a + S c
};

// `kept`: the directions kept before p (not changed); `min_rescale`: the rule's threshold
// (LearnedParams). proposal_value and proposal_gradient are L and its masked gradient at a + p.
SubspaceStepOutcome energy_after_subspace_step(StepProblem& problem, const SecantSubspace& kept, double min_rescale,
                                               const VecX& a, const VecX& start_gradient, const VecX& proposal,
                                               double proposal_value, const VecX& proposal_gradient);

}  // namespace fnopt
