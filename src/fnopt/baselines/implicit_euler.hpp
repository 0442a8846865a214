#pragma once
// Linearly implicit Euler, the one-solve step of ARCSim and Blender (Baraff & Witkin 1998,
// "Large steps in cloth simulation"): the forces are linearised once, at the start of the step,
// and one linear system is solved; no iteration, no line search. In fnopt's unknowns (the
// acceleration a, cloth/backward_euler.hpp) that is one Newton step on L from
//   a_0: x(a_0) = x_t on the free vertices (a_0 = -v_t/dt), the handles at their targets,
//   H(a_0) d = -g(a_0),   a = a_0 + d,
// with each stencil's Hessian projected to PSD (cloth/psd_projection.hpp), as those solvers
// need a definite system. Without handles this is exactly Baraff & Witkin's
//   (M - dt^2 df/dx) dv = dt (f_t + dt df/dx v_t),  dv = dt a.
// The budget is one solve per step whatever the iteration count; the error against the exact
// backward-Euler step (Newton) is the linearisation's, which grows with the step's rotation.
#include <optional>
#include <string>

#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>

namespace fnopt {

class ImplicitEulerOptimizer final : public InnerOptimizer {
 public:
  std::string name() const override { return "implicit-euler"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  // The one solve; a second call in the same step returns IterationBudget.
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

 private:
  SparseCholesky cholesky_;
  bool solved_ = false;
  VecX start_gradient_, rhs_;
};

}  // namespace fnopt
