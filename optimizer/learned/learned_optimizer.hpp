#pragma once
// The learned inner optimizer (DESIGN.md §4) behind the common interface: a meta-trained FNO
// proposes each update from the gradient (learned_update.hpp). The recurrent state is reset
// at every time step except the step scale s, which carries over: it adapts to the stiffness
// of the scene. One instance serves one rollout (or one grid); no autograd at inference.
//
// Energy safeguard (fnopt's addition, on by default): an update that raises L or is not finite
// is undone and s shrinks by 4, so the energy of a step never increases and a model that is
// wrong at some resolution slows down instead of blowing up. It costs nothing for an accepted
// update (L comes with the gradient needed next anyway). Measured: without it the 32^2-trained
// model diverged within 4 steps at 64^2 and 100^2.
//
// Step length along the learned direction (fnopt's addition, optional: "fnopt-ls"). The FNO
// proposes p = delta; with L's gradient at both ends, the secant of the directional
// derivative, alpha = g(a).p / (g(a).p - g(a+p).p), is the exact minimiser along p for a
// quadratic L. When alpha is far from 1 the iterate moves to a + alpha p (one more gradient),
// kept only if it lowers L further; the recurrent state then sees the update alpha p and s
// scales by alpha, so the next proposal starts from the length that worked.
//
// Subspace step (fnopt's addition, optional: "fnopt-ss"). The secant step generalised to the
// last K proposals: each proposal p with its gradient difference g(a+p) - g(a) is one secant
// pair, and the iterate moves to the minimiser of the quadratic model of L over their span
// (a conjugate-direction step with the FNO as the preconditioner), kept only if it lowers L.
// The pairs are carried across time steps. The recurrent state and s see the coefficient of
// the newest proposal, as they see alpha above.
#include <memory>
#include <string>

#include "fno/fno2d.hpp"
#include "optimizer/inner_optimizer.hpp"
#include "optimizer/secant_subspace.hpp"
#include "optimizer/learned/learned_update.hpp"

namespace fnopt {

struct LearnedParams {
  bool safeguard = true;     // undo updates that raise L (or are not finite), shrink s by 4
  bool line_search = false;  // rescale each update by the secant step along it
  // The secant step is taken only when |alpha - 1| exceeds this: near 1 the extra gradient
  // buys little.
  double min_rescale = 0.2;
  // alpha is clamped to [1 / max_rescale, max_rescale]: the secant of a far-from-quadratic
  // L can point anywhere.
  double max_rescale = 10.0;
  // Subspace step ("fnopt-ss"; 0: off, else it replaces line_search): the iterate moves to the
  // minimiser of the secant model of L over the last `subspace` proposals
  // (optimizer/secant_subspace.hpp) when that lowers L further.
  int subspace = 0;
  // Keep the proposals and their gradient differences from one time step to the next: the step
  // Hessian changes little between steps, so the first iterations of a step already minimise
  // over the previous step's directions. Only into the step that continues the previous one
  // (its start is x_t + dt v_{t+1}); any other state, such as the next sample of the per-step
  // error bench or a new grid, starts empty.
  bool carry_subspace = true;

  void validate() const;  // Error("fnopt: ...") for values out of range
};

class LearnedOptimizer final : public InnerOptimizer {
 public:
  // Loads the model file (Error naming the file if it is missing or not a learned optimizer).
  explicit LearnedOptimizer(const std::string& model_path, LearnedParams params = {});
  LearnedOptimizer(FNO2d model, std::string model_name, LearnedParams params = {});

  std::string name() const override;
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

 private:
  // Moves a (with value and gradient) to previous_a_ + alpha (a - previous_a_) if that lowers
  // L; returns the alpha applied (1 if none).
  double rescale_update(StepProblem& problem, VecX& a, double& value, VecX& gradient);
  // Evaluates L at trial_ and moves a (with value and gradient) there if that is lower than
  // value; the secant and the subspace step both end with this.
  bool take_trial_if_lower(StepProblem& problem, VecX& a, double& value, VecX& gradient);
  // Moves a to previous_a_ + S c, the subspace model's minimiser, if that lowers L; returns
  // the coefficient of the newest proposal (1 if the step was not taken).
  double subspace_update(StepProblem& problem, VecX& a, double& value, VecX& gradient);
  // Whether the objective's step starts where the previous step (started at previous_start_)
  // ends, to round-off.
  bool continues_previous_step(const BackwardEulerObjective& objective) const;
  static constexpr double kContinuationTolerance = 1e-12;

  FNO2d model_;
  std::string model_name_;
  LearnedParams params_;
  LearnedState state_;
  VecX previous_a_, previous_gradient_, direction_, trial_, trial_gradient_, gradient_change_;
  VecX previous_start_;  // x_t of the previous step (subspace only)
  SecantSubspace subspace_;
  torch::Tensor mask_;
  const DirichletSet* mask_owner_ = nullptr;
};

}  // namespace fnopt
