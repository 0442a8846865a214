#pragma once
// The learned inner optimizer (DESIGN.md §4) behind the common interface: a meta-trained FNO
// proposes each update from the gradient (learned_update.hpp). The recurrent state is reset
// at every time step except the step scale s, which carries over: it adapts to the stiffness
// of the scene. One instance serves one rollout (or one grid); no autograd at inference.
#include <memory>
#include <string>

#include "fno/fno2d.hpp"
#include "optimizer/inner_optimizer.hpp"
#include "optimizer/learned/learned_update.hpp"

namespace fnopt {

class LearnedOptimizer final : public InnerOptimizer {
 public:
  // Loads the model file (Error naming the file if it is missing or not a learned optimizer).
  explicit LearnedOptimizer(const std::string& model_path);
  LearnedOptimizer(FNO2d model, std::string model_name);

  std::string name() const override { return "fnopt"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

 private:
  FNO2d model_;
  std::string model_name_;
  LearnedState state_;
  torch::Tensor mask_;
  const DirichletSet* mask_owner_ = nullptr;
};

}  // namespace fnopt
