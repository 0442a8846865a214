#pragma once
// The Newton reference solve (DESIGN.md §6): it defines the exact backward-Euler step of the
// energy, the ground truth of every error fnopt reports. Each iteration solves
//   H d = -g,   then   a <- a + alpha d   (backtracking until Armijo's condition holds),
// run by solve_step() to ||g|| <= 1e-9 ||g_0|| over the free dofs (reference_solve_options()).
//
// H is the exact Hessian where it is positive definite (quadratic convergence near a minimum);
// where it is not (compressed or buckling cloth), that iteration uses the projected Hessian
// (per-stencil, negative eigenvalues flipped: cloth/psd_projection.hpp), positive definite
// thanks to the mass term.
//
// Linear solves: a sparse Cholesky factor (CHOLMOD supernodal on OpenBLAS) costs ~20x a
// triangular solve at 100^2, and H changes little from one iteration or time step to the next.
// So the factor of an earlier H preconditions conjugate gradients on the current H, solved to
// the relative residual min(forcing_cap, ||g||/||g_0||) (inexact Newton, Eisenstat & Walker
// 1996: the forcing term shrinking like ||g|| keeps the convergence quadratic); only when CG
// needs more than max_cg_iterations is H refactorized and solved directly.
#include <Eigen/CholmodSupport>

#include "optimizer/inner_optimizer.hpp"

namespace fnopt {

struct NewtonParams {
  double armijo = 1e-4;             // sufficient-decrease constant c1
  double backtrack = 0.5;           // step shrink factor per line-search trial
  int max_backtracks = 40;
  double forcing_cap = 1e-2;        // largest relative residual accepted from CG
  int max_cg_iterations = 20;       // beyond this, refactorize (0: always factorize)

  void validate() const;  // throws Error naming the parameter
};

// Work counters, for benchmarks.
struct NewtonCounters {
  long factorizations = 0;
  long cg_iterations = 0;
  long projected_iterations = 0;  // iterations that used the projected Hessian
};

class NewtonOptimizer final : public InnerOptimizer {
 public:
  explicit NewtonOptimizer(NewtonParams params = {});

  // The reference: converged to ||g|| <= 1e-9 ||g_0||. Most steps take 3-10 iterations; near
  // a saddle of compressed, buckling cloth it takes longer (on the 32^2 benchmark at most 157),
  // hence the generous cap.
  static InnerSolveOptions reference_solve_options() { return {300, 1e-9}; }

  std::string name() const override { return "newton"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value,
                                     VecX& gradient) override;

  const NewtonCounters& counters() const { return counters_; }

 private:
  enum class CgOutcome { Converged, NegativeCurvature, TooManyIterations };
  // Preconditioned CG on H d = b with the current factor; d starts at 0.
  CgOutcome preconditioned_cg(const Eigen::SparseMatrix<double>& H, const VecX& b, double tolerance);
  // Factorizes H (false if it is not positive definite) and solves H d = b directly.
  bool factorize_and_solve(const Eigen::SparseMatrix<double>& H, const VecX& b);
  // Computes direction_ for the Hessian at a; returns false if no PD Hessian could be factorized.
  bool newton_direction(StepProblem& problem, const VecX& a, double tolerance);

  NewtonParams params_;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt_;
  const void* analysed_pattern_ = nullptr;
  bool have_factor_ = false;
  NewtonCounters counters_;
  double initial_gradient_norm_ = 0.0;
  double start_value_ = 0.0;
  VecX trial_, trial_gradient_, rhs_, direction_, residual_, preconditioned_, search_, product_;
};

}  // namespace fnopt
