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
#include <memory>
#include <string>

#include "fno/fno2d.hpp"
#include "optimizer/inner_optimizer.hpp"
#include "optimizer/learned/learned_update.hpp"

namespace fnopt {

class LearnedOptimizer final : public InnerOptimizer {
 public:
  // Loads the model file (Error naming the file if it is missing or not a learned optimizer).
  explicit LearnedOptimizer(const std::string& model_path, bool safeguard = true);
  LearnedOptimizer(FNO2d model, std::string model_name, bool safeguard = true);

  std::string name() const override { return "fnopt"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

 private:
  FNO2d model_;
  std::string model_name_;
  bool safeguard_;
  LearnedState state_;
  VecX previous_a_, previous_gradient_;
  torch::Tensor mask_;
  const DirichletSet* mask_owner_ = nullptr;
};

}  // namespace fnopt
