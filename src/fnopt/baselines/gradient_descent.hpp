#pragma once
// Gradient descent with a fixed step (docs/design.md §6), in the mass metric of first_order.hpp:
//   a <- a - (learning_rate / lambda) * P^-1 g,      P = dt^2 M,
// where lambda estimates the largest eigenvalue of P^-1 H (H the Hessian of the step objective)
// by power iteration when the optimizer first meets an objective (curvature_scaled, default).
// learning_rate is then dimensionless and means the same at every resolution and material:
// 1 is the classical 1/L step, and a quadratic diverges above 2. The stiffest modes then
// converge in a few iterations and the smoothest ones (eigenvalue ~1: the cloth swinging as a
// whole) at the rate 1 - learning_rate/lambda per iteration, with lambda ~ 1 + 4 k~_s ~ 1700 at
// 32^2 for the default material: that slowness is GD's failure mode the paper reports.
// With curvature_scaled = false, lambda = 1: the step is learning_rate times the exact step of
// the inertia term alone (P^-1 g, an acceleration), for users who want to set it by hand.
#include <fnopt/baselines/first_order.hpp>

namespace fnopt {

struct GradientDescentParams {
  double learning_rate = 1.0;    // in units of 1/lambda (curvature_scaled) or of P^-1 g
  bool curvature_scaled = true;  // divide the step by the estimated lambda_max(P^-1 H)
  int power_iterations = 20;     // gradient evaluations spent once per objective on lambda

  void validate() const;  // throws Error naming the parameter
};

class GradientDescentOptimizer final : public FirstOrderOptimizer {
 public:
  explicit GradientDescentOptimizer(GradientDescentParams params = {});

  std::string name() const override { return "gd"; }
  std::string settings() const override;
  void begin(SmoothProblem& problem, const VecX& x, double value, const VecX& gradient) override;
  std::optional<SolveStatus> step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) override;

  // The estimated lambda_max(P^-1 H) (1 when not curvature_scaled; 0 before the first step).
  double curvature() const { return curvature_; }

 protected:
  void on_new_problem() override { curvature_ = 0.0; }

 private:
  GradientDescentParams params_;
  double curvature_ = 0.0;
};

}  // namespace fnopt
