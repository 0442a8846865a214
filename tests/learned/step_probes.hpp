#pragma once
// Wrappers that watch an inner optimizer from outside, for the learned optimizers' tests.
#include <vector>

#include <fnopt/optimizer/inner_optimizer.hpp>

namespace fnopt {

// Records L after every iteration of the wrapped optimizer, and the slope of L along each
// update d = a_after - a_before at its end relative to its start, g(a_after).d / g(a_before).d.
class EnergyLog final : public InnerOptimizer {
 public:
  explicit EnergyLog(InnerOptimizer& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  std::string settings() const override { return inner_.settings(); }
  void begin_step(StepProblem& p, const VecX& a, double value, const VecX& g) override {
    values = {value};
    inner_.begin_step(p, a, value, g);
  }
  std::optional<SolveStatus> iterate(StepProblem& p, VecX& a, double& value, VecX& g) override {
    const VecX a_before = a, g_before = g;
    const auto status = inner_.iterate(p, a, value, g);
    values.push_back(value);
    const VecX d = a - a_before;
    if (d.norm() > 0.0) slope_ratios.push_back(g.dot(d) / g_before.dot(d));
    return status;
  }
  std::vector<double> values;
  std::vector<double> slope_ratios;  // of the iterations that moved a

 private:
  InnerOptimizer& inner_;
};

// Drives a rollout with `main` while every shadow solves each step from the same start with its
// own budget; a shadow keeps its state from step to step, as in a rollout of its own.
class Shadows final : public InnerOptimizer {
 public:
  Shadows(InnerOptimizer& main, std::vector<InnerOptimizer*> shadows, InnerSolveOptions options)
      : main_(main), shadows_(std::move(shadows)), options_(options), values(shadows_.size()) {}
  std::string name() const override { return main_.name(); }
  std::string settings() const override { return main_.settings(); }
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override {
    for (std::size_t k = 0; k < shadows_.size(); ++k) {
      VecX shadow_a = a;
      values[k].push_back(solve_step(*shadows_[k], problem, shadow_a, options_).value);
    }
    main_.begin_step(problem, a, value, gradient);
  }
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    return main_.iterate(problem, a, value, gradient);
  }

 private:
  InnerOptimizer& main_;
  std::vector<InnerOptimizer*> shadows_;
  const InnerSolveOptions options_;

 public:
  // Per shadow, L at the end of every step (declared after shadows_, which sizes it).
  std::vector<std::vector<double>> values;
};

}  // namespace fnopt
