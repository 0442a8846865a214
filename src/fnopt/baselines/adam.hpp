#pragma once
// Adam (Kingma & Ba 2015; docs/design.md §6) on the preconditioned gradient u = P^-1 g of
// first_order.hpp (an acceleration [m/s^2] on the cloth):
//   m <- b1 m + (1 - b1) u,   v <- b2 v + (1 - b2) u^2,
//   a <- a - learning_rate * step_unit * m^ / (sqrt(v^) + epsilon),   m^, v^ bias-corrected.
// Adam is invariant to a per-dof scaling of the gradient, so the metric only sets the units of
// epsilon (m/s^2, negligible against the ~10 m/s^2 of gravity, where on the raw ~1e-7 gradient
// 1e-8 would not be). Each iteration moves every free dof by at most ~learning_rate *
// step_unit, so learning_rate is in grid units: cell widths per step^2 (step_unit = h/dt^2, the
// unit of the learned optimizer's step s), i.e. 0.003 moves a vertex by at most 0.3 % of a cell
// per iteration at any resolution. The default 0.003 had the lowest mean per-step error
// (studies/compare/step_error.hpp, 16 states of the 390-frame 32^2 xy_v2 Newton rollout) among
// {3e-4, 1e-3, 3e-3, 1e-2} for N = 10 and N = 500, and the second lowest for N = 100 (1e-2). Moments and the bias
// correction restart every time step. `fnopt compare` sweeps learning_rate per budget (a small budget needs a larger
// rate).
#include <fnopt/baselines/first_order.hpp>

namespace fnopt {

struct AdamParams {
  double learning_rate = 3e-3;  // grid units (cell widths per step^2) per iteration
  double beta1 = 0.9;
  double beta2 = 0.999;
  double epsilon = 1e-8;  // in the units of P^-1 g

  void validate() const;  // throws Error naming the parameter
};

class AdamOptimizer final : public FirstOrderOptimizer {
 public:
  explicit AdamOptimizer(AdamParams params = {});

  std::string name() const override { return "adam"; }
  std::string settings() const override;
  void begin(SmoothProblem& problem, const VecX& x, double value, const VecX& gradient) override;
  std::optional<SolveStatus> step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) override;

 private:
  AdamParams params_;
  VecX first_moment_, second_moment_, preconditioned_;
  int iteration_ = 0;
  double beta1_power_ = 1.0, beta2_power_ = 1.0;
};

}  // namespace fnopt
