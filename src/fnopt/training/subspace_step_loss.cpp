#include <fnopt/training/subspace_step_loss.hpp>

#include <cmath>

namespace fnopt {
namespace {

// H(x) u by a central difference of the masked gradient, the step a 1e-4 of |p| along u: small
// against the scale on which L's curvature changes, large against the gradient's rounding.
VecX hessian_product(StepProblem& problem, const VecX& x, const VecX& u, double proposal_norm) {
  const double u_norm = u.norm();
  if (!(u_norm > 0.0) || !(proposal_norm > 0.0)) return VecX::Zero(u.size());
  const double h = 1e-4 * proposal_norm / u_norm;
  VecX plus, minus;
  problem.value_gradient(x + h * u, plus);
  problem.value_gradient(x - h * u, minus);
  return (plus - minus) / (2.0 * h);
}

}  // namespace

SubspaceStepOutcome energy_after_subspace_step(StepProblem& problem, const SecantSubspace& kept, double min_rescale,
                                               const VecX& a, const VecX& start_gradient, const VecX& proposal,
                                               double proposal_value, const VecX& proposal_gradient) {
  SubspaceStepOutcome outcome{proposal_value, proposal_gradient, false};
  SecantSubspace pairs = kept;
  if (!std::isfinite(proposal_value) || !pairs.push(proposal, proposal_gradient - start_gradient)) return outcome;
  const SecantSubspace::Coefficients c = pairs.minimiser(start_gradient);
  VecX step;
  pairs.combine(c, step);
  // As ProposalRule: a subspace step that hardly differs from p is not taken.
  if ((step - proposal).norm() <= min_rescale * proposal.norm()) return outcome;
  VecX end_gradient;
  const double end_value = problem.value_gradient(a + step, end_gradient);
  if (!(end_value < proposal_value) || !end_gradient.allFinite()) return outcome;

  const int newest = pairs.size() - 1;
  const SecantSubspace::Coefficients w = -pairs.minimiser(end_gradient);  // M^+ S^T g'
  VecX s_w;
  pairs.combine(w, s_w);
  VecX y_c, y_w;
  pairs.combine_changes(c, y_c);
  pairs.combine_changes(w, y_w);
  const VecX u = 0.5 * (c(newest) * s_w + w(newest) * step);
  outcome.gradient = c(newest) * end_gradient - w(newest) * start_gradient - 0.5 * (w(newest) * y_c + c(newest) * y_w) -
                     hessian_product(problem, a + proposal, u, proposal.norm());
  outcome.value = end_value;
  outcome.taken = true;
  return outcome;
}

}  // namespace fnopt
