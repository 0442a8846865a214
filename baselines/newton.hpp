#pragma once
// The Newton reference solve (docs/design.md §6): it defines the exact backward-Euler step of the
// energy, the ground truth of every error fnopt reports. Each iteration solves
//   H d = -g,   then   a <- a + alpha d   (backtracking until Armijo's condition holds),
// run by solve_step() to ||g|| <= 1e-9 ||g_0|| over the free dofs (reference_solve_options()).
//
// H is the exact Hessian where it is positive definite (quadratic convergence near a minimum).
// Where it is not (compressed or buckling cloth), that iteration adds a multiple of the inertia
// term, H + mu dt^2 M, with the smallest mu of a geometric sequence for which Cholesky succeeds
// (Nocedal & Wright 2006, Alg. 3.3, in the mass metric): the step keeps the exact curvature
// everywhere else and moves along the negative-curvature directions instead of stalling near a
// saddle. The per-stencil projected Hessian (negative eigenvalues flipped:
// cloth/psd_projection.hpp) is the last resort; on its own it needed up to 300 iterations on
// the first, buckling steps of the 64^2 benchmark.
//
// Linear solves: a sparse Cholesky factor (CHOLMOD supernodal on OpenBLAS) costs ~20x a
// triangular solve at 100^2, and H changes little from one iteration or time step to the next.
// So the factor of an earlier H preconditions conjugate gradients on the current H, solved to
// the relative residual min(forcing_cap, ||g||/||g_0||) (inexact Newton, Eisenstat & Walker
// 1996: the forcing term shrinking like ||g|| keeps the convergence quadratic); only when CG
// needs more than max_cg_iterations is H refactorized and solved directly.
#include <Eigen/CholmodSupport>

#include "optimizer/inner_optimizer.hpp"
#include "optimizer/line_search.hpp"
#include "baselines/pqn_matrix.hpp"
#include <memory>

namespace fnopt {

struct NewtonParams {
  // The backtracking line search (optimizer/line_search.hpp).
  double armijo = 1e-4;             // sufficient-decrease constant c1
  double backtrack = 0.5;           // step shrink factor per line-search trial
  int max_backtracks = 40;
  double forcing_cap = 1e-2;        // largest relative residual accepted from CG
  int max_cg_iterations = 20;       // beyond this, refactorize (0: always factorize)
  // Where the exact Hessian is indefinite: H + mu dt^2 M (mu relative to the inertia term),
  // mu grown by shift_growth until Cholesky succeeds. The search starts at the last mu /
  // shift_growth while the iterates stay shifted, so the shift decays as they leave a saddle.
  // Above max_shift the per-stencil projected Hessian is used instead. 0 disables the shift.
  // Growth 2 keeps mu within a factor 2 of the most negative curvature: first 40 frames of the
  // 64^2 benchmark, 305 ms/frame and at most 74 iterations, against 389 ms and 160 with 4,
  // 507 ms and one unconverged step with 8, 487 ms with 1.25 (more trials per iteration).
  double max_shift = 1e6;
  double shift_growth = 2.0;
  // A stall guard for the shift. Where the negative curvature is strong and persists (64^2
  // benchmark, motion xz_v2, step 114: H + mu dt^2 M indefinite up to mu ~ 105, so mu = 210), the
  // shift damps every soft mode by mu as well, and ||g|| falls by ~0.5 % per iteration: 200
  // iterations ended at ||g|| = 6e-3 ||g_0||. After max_slow_shifted_iterations consecutive
  // shifted iterations that each lower ||g|| by less than a factor slow_shift_progress, one
  // iteration uses the per-stencil projected Hessian instead, which changes only the compressed
  // stencils; its factor then preconditions CG on the exact Hessian (there: 47 iterations).
  // The projection cannot replace the shift everywhere (as the only fallback: 552 iterations on
  // a 64^2 xy_v2 buckling step, against 74), so the guard waits: the longest slow run measured on
  // 64^2 xy_v2 is 28 (step 31), and the references of the other benchmark motions (32^2: all 15,
  // 64^2: 8, 100^2: 3) are bit-identical with it. 0 disables the guard.
  int max_slow_shifted_iterations = 40;
  double slow_shift_progress = 0.9;
  // Preconditioner of CG: the factor of an earlier Hessian (refactorized when CG is slow), or
  // the fixed prefactored matrix of pqn (baselines/pqn_matrix.hpp), factorized once per scene,
  // with the shift also searched by CG; factorizations of H only where that fails. The pqn
  // matrix measured slower (docs/results.md, "Newton reference"): the exact Hessian's soft
  // transverse modes are far from its isotropic springs, so CG needs ~860 iterations per step
  // at 32^2 to the reference tolerance, 3.5x the time of the earlier factor's.
  bool pqn_preconditioner = false;
  int max_pqn_cg_iterations = 300;

  void validate() const;  // throws Error naming the parameter
  BacktrackingParams line_search() const { return {armijo, backtrack, max_backtracks}; }
};

// Work counters, for benchmarks.
struct NewtonCounters {
  long factorizations = 0;
  long cg_iterations = 0;
  long projected_iterations = 0;  // iterations that used the projected Hessian
  long shifted_iterations = 0;    // iterations that used H + mu dt^2 M
  long stalled_shifts = 0;        // times the stall guard replaced the shift by the projection
};

class NewtonOptimizer final : public InnerOptimizer {
 public:
  explicit NewtonOptimizer(NewtonParams params = {});

  // The reference: converged to ||g|| <= 1e-9 ||g_0||. Most steps take 3-10 iterations; where
  // compressed cloth starts to buckle it takes longer (benchmark scene: at most 27 at 32^2 and 74
  // at 64^2; at 100^2 one step slides along a nearly neutral mode for 626), hence the generous cap.
  static InnerSolveOptions reference_solve_options() { return {1000, 1e-9}; }

  std::string name() const override { return "newton"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value,
                                     VecX& gradient) override;

  const NewtonCounters& counters() const { return counters_; }

 private:
  enum class CgOutcome { Converged, NegativeCurvature, TooManyIterations };
  // Preconditioned CG on (H + shift D) d = b, D = diag(shift_diagonal) (ignored when shift is 0),
  // with `precondition(r)` applying the preconditioner in place; d starts at 0.
  template <class Precondition>
  CgOutcome preconditioned_cg(const Eigen::SparseMatrix<double>& H, double shift, const VecX& b, double tolerance,
                              int max_iterations, Precondition&& precondition);
  // The pqn-preconditioned direction: CG on H, then on H + mu dt^2 M for growing mu.
  bool pqn_direction(StepProblem& problem, const Eigen::SparseMatrix<double>& H, double tolerance);
  void set_inertia_diagonal(StepProblem& problem);
  // Factorizes H (false if it is not positive definite) and solves H d = b directly. `pattern`
  // is the objective's hessian_pattern_id(): the symbolic analysis is redone when it changes.
  bool factorize_and_solve(const Eigen::SparseMatrix<double>& H, const VecX& b, long pattern);
  // Factorizes H + mu dt^2 M for growing mu until Cholesky succeeds (false above max_shift).
  bool shifted_solve(StepProblem& problem, const Eigen::SparseMatrix<double>& H, const VecX& b, double start);
  // Computes direction_ for the Hessian at a; returns false if no PD Hessian could be factorized.
  bool newton_direction(StepProblem& problem, const VecX& a, double tolerance);

  NewtonParams params_;
  std::unique_ptr<PqnFactorCache> pqn_;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt_;
  long analysed_pattern_ = -1;
  bool have_factor_ = false;
  NewtonCounters counters_;
  double initial_gradient_norm_ = 0.0;
  double start_value_ = 0.0;
  static constexpr double kMinShift = 1e-4;  // smaller shifts are no better than none
  double shift_ = 0.0;        // the last mu that made H + mu dt^2 M positive definite
  bool last_shifted_ = false;  // whether the last iteration used it
  int slow_shifted_iterations_ = 0;    // consecutive shifted iterations with little gain in ||g||
  double previous_gradient_norm_ = 0.0;
  Eigen::SparseMatrix<double> shifted_;
  VecX inertia_diagonal_;  // dt^2 m per free dof
  VecX rhs_, direction_, full_direction_, residual_, preconditioned_, search_, product_;
  LineSearchScratch line_search_;
};

}  // namespace fnopt
