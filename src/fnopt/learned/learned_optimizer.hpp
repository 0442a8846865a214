#pragma once
// The learned inner optimizer (docs/design.md §4) behind the common interface: a meta-trained FNO
// proposes each update from the gradient (learned_update.hpp). The recurrent state is reset
// at every time step except the step scale s, which carries over: it adapts to the stiffness
// of the scene. One instance serves one rollout (or one grid); no autograd at inference.
//
// What happens to each proposal (the energy safeguard, the optional secant or subspace step) is
// the proposal rule (proposal_rule.hpp), shared with meta-training. The rule's proposals are
// carried into the next time step only when that step continues the previous one. With
// LearnedParams::pqn_direction ("fnopt") the rule first adds pqn's preconditioned gradient
// to its subspace at each iteration; a model that reads pqn's direction (learned_update.hpp) gets
// it computed at each iteration, with or without that pair.
#include <memory>
#include <string>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/learned/proposal_rule.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>

namespace fnopt {

class LearnedOptimizer final : public InnerOptimizer {
 public:
  // Loads the model file (Error naming the file if it is missing or not a learned optimizer).
  // `method_name`, if given, is the name it reports instead of its rule's (a registry name such
  // as fnopt-ss-32, the same rule on another default model).
  explicit LearnedOptimizer(const std::string& model_path, LearnedParams params = {}, std::string method_name = {});
  LearnedOptimizer(FNO2d model, std::string model_name, LearnedParams params = {});

  std::string name() const override;
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

  // The recurrent state after the last iteration: its step scale s is what the scale head has
  // made of the scene so far (a diagnostic, docs/design.md §4).
  const LearnedState& state() const { return state_; }

 private:
  // Whether the objective's step starts where the previous step (started at previous_start_)
  // ends, to round-off.
  bool continues_previous_step(const BackwardEulerObjective& objective) const;
  static constexpr double kContinuationTolerance = 1e-12;

  FNO2d model_;
  std::string model_name_;
  std::string method_name_;  // empty: the rule's name
  ProposalRule rule_;
  LearnedState state_;
  VecX previous_start_;  // x_t of the previous step (subspace only)
  torch::Tensor mask_;
  const DirichletSet* mask_owner_ = nullptr;
};

}  // namespace fnopt
