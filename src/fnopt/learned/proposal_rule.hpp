#pragma once
// What the learned optimizer does with one proposal of the FNO. Inference (learned_optimizer.hpp)
// and meta-training (meta_trainer.hpp) share it, so that a pool trained with a rule visits the
// states the same rule produces at inference.
//   1. a <- a + p, with L and its masked gradient there (the next proposal needs them anyway).
//   2. Optionally a step along the proposals, kept only if it lowers L further:
//      - the secant step along p ("fnopt-ls"): alpha = g(a).p / (g(a).p - g(a+p).p), the exact
//        minimiser along p for a quadratic L;
//      - or the subspace step ("fnopt-ss"): the minimiser of the secant model of L over the span
//        of the last K proposals (optimizer/secant_subspace.hpp), a conjugate-direction step
//        with the FNO as the preconditioner; K = 1 is the secant step.
//   3. The energy safeguard: if L rose from where the proposal started, or is not finite, a goes
//      back there and s shrinks by 4. It costs nothing for an accepted update.
// The next proposal sees the gradient this one was made from, the update as applied along p
// (alpha p, with alpha the newest proposal's coefficient) and s alpha, so it starts from the
// length that worked.
#include <string>

#include <fnopt/baselines/pqn_matrix.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/optimizer/secant_subspace.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

// fnopt-ss keeps the last eight proposals, carried across time steps: fewer were further from
// Newton on fine grids, more were no better (docs/design.md §4).
inline constexpr int kFnoptSubspace = 8;

struct LearnedParams {
  bool safeguard = true;     // undo updates that raise L (or are not finite), shrink s by 4
  bool line_search = false;  // rescale each update by the secant step along it
  // The secant step is taken only when |alpha - 1| exceeds this (near 1 the extra gradient buys
  // little), and the subspace step only when it differs from p by more than this much of |p|.
  double min_rescale = 0.2;
  // alpha is clamped to [1 / max_rescale, max_rescale]: the secant of a far-from-quadratic
  // L can point anywhere.
  double max_rescale = 10.0;
  // Subspace step ("fnopt-ss"; 0: off, else it replaces line_search): the iterate moves to the
  // minimiser of the secant model of L over the last `subspace` proposals when that lowers L
  // further.
  int subspace = 0;
  // Keep the proposals and their gradient differences from one time step to the next: the step
  // Hessian changes little between steps, so the first iterations of a step already minimise
  // over the previous step's directions. Only into the step that continues the previous one
  // (its start is x_t + dt v_{t+1}); any other state, such as the next sample of the per-step
  // error bench or a new grid, starts empty.
  bool carry_subspace = true;
  // Also put pqn's preconditioned gradient in the subspace ("fnopt"; needs `subspace`):
  // before each proposal, the pair (d, g(a + d) - g(a)) with d = -A^-1 g(a), A pqn's isotropic
  // matrix (baselines/pqn_matrix.hpp), joins the kept pairs without moving a, so the subspace
  // step minimises over the FNO's directions and A's. A holds the grid's stiffness, which the
  // FNO's normalised inputs do not: without it the learned step's error grows with the grid
  // (docs/design.md §4). One more gradient and one solve with A's factor per iteration; the
  // training pool takes it too when `fnopt train --pqn-direction` asks (training_env.hpp).
  bool pqn_direction = false;

  void validate() const;  // Error("fnopt.<field>: ...") for values out of range
};

// Error("<field>: ...") unless 0 <= subspace <= SecantSubspace::kMaxCapacity (0: no subspace
// step); for every option that sets a rule's `subspace`.
void require_subspace_size(int subspace, const std::string& field);

class ProposalRule {
 public:
  explicit ProposalRule(LearnedParams params);

  const LearnedParams& params() const { return params_; }
  // The proposals kept for the subspace step (checkpoints save and restore them).
  SecantSubspace& pairs() { return subspace_; }
  const SecantSubspace& pairs() const { return subspace_; }

  // Called before each proposal is made, a staying where it is. With LearnedParams::pqn_direction,
  // adds the pair (d, g(a + d) - g(a)) with d = -A^-1 g at a (g: the masked gradient there) to
  // the kept pairs. Nothing otherwise.
  void add_pqn_direction(StepProblem& problem, const VecX& a, const VecX& gradient);

  // Applies `proposal` (grid units, coordinate samples [3, 1, R, C]) made from the masked gradient samples
  // `gradient_samples` at a. On entry value and gradient are L and its masked gradient at a; on
  // return they are those of the new iterate. Returns the recurrent state for the next proposal.
  LearnedState apply(StepProblem& problem, const torch::Tensor& gradient_samples, const LearnedStep& proposal, VecX& a,
                     double& value, VecX& gradient);

 private:
  // Moves a (with value and gradient) to start_ + alpha (a - start_) if that lowers L; returns
  // the alpha applied (1 if none).
  double secant_update(StepProblem& problem, VecX& a, double& value, VecX& gradient);
  // Moves a to start_ + S c, the subspace model's minimiser, if that lowers L; returns the
  // coefficient of the newest proposal (1 if the step was not taken).
  double subspace_update(StepProblem& problem, VecX& a, double& value, VecX& gradient);
  // Evaluates L at trial_ and moves a (with value and gradient) there if that is lower than
  // value; both steps end with this.
  bool take_trial_if_lower(StepProblem& problem, VecX& a, double& value, VecX& gradient);

  LearnedParams params_;
  SecantSubspace subspace_;
  // Where the proposal started, and scratch reused from one proposal to the next.
  VecX start_, start_gradient_, direction_, trial_, trial_gradient_, gradient_change_, pqn_step_;
  PqnFactorCache pqn_factor_;
};

}  // namespace fnopt
