#pragma once
// The Newton reference solve (docs/design.md §6): it defines the exact backward-Euler step of the
// energy, the ground truth of every error fnopt reports. A trust-region Newton method (Nocedal &
// Wright 2006, Alg. 4.1) on the exact Hessian H, each subproblem solved by Steihaug–Toint CG
// (linalg/steihaug_cg.hpp) preconditioned by one positive-definite matrix,
//   P = dt^2 M (1 + c dt) + dt^4 K+,   K+ the per-stencil PSD-projected elastic Hessian,
// which is built rarely: its sparse Cholesky factor (on fine grids, a multigrid V-cycle on it) is
// kept across iterations and time steps and rebuilt only when a subproblem needed more than
// refactor_cg_iterations products with H.
// The trust region is measured in the mass metric W = dt^2 M (1 + c dt), ||d||_W = sqrt(d.W d):
// P's own norm holds |negative curvature| of the compressed stencils and so made the region
// tightest along the very buckling directions a step must take (docs/design.md §6).
//
// Why this shape: where the cloth is compressed H is indefinite. CG then meets a direction of
// negative curvature only if the gradient has a component along it, and follows it to the
// region's boundary, a descent at the rate the region allows (buckling); where it has none (a
// symmetric, unbuckled saddle) CG never sees it and the iteration converges there quadratically,
// the branch ARCSim's one linear solve takes (docs/design.md §6, "What the reference converges
// to"). No Cholesky of an indefinite matrix is tried, and no shift damps the soft modes.
//
// With contact each trial is the feasible part of the step (the CCD filter every iterate passes,
// docs/design.md §14), judged against the model along that cut step, and the region is sized from
// the step taken: L falls from every iterate to the next.
//
// The reference stops on the residual acceleration max_i |g_i| / (m_i dt^2) (m/s^2), which is
// a - f(x)/m, the part of Newton's second law the step leaves unbalanced
// (reference_solve_options()); its size against the errors it measures is in docs/design.md §6.
#include <fnopt/linalg/block_multigrid.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/linalg/single_precision_factor.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/linalg/steihaug_cg.hpp>

namespace fnopt {

struct NewtonParams {
  // The trust region (Nocedal & Wright Alg. 4.1). Each time step starts with the radius
  // initial_radius x ||P^-1 g_0||_W, the length of the preconditioned gradient step.
  double initial_radius = 2.0;
  double accept_ratio = 1e-4;  // eta: a trial is taken when actual / predicted decrease > eta
  double shrink_below = 0.25;  // below this ratio the radius shrinks to shrink x ||d||_W
  double shrink = 0.25;
  double grow_above = 0.75;  // above it a step that reached the boundary doubles the radius
  int max_trials = 40;       // rejected trials per iteration before line-search-failed
  // CG per subproblem to the relative residual min(forcing_cap, ||g|| / ||g_0||) (inexact Newton,
  // Eisenstat & Walker 1996: the forcing term shrinking like ||g|| keeps convergence quadratic).
  double forcing_cap = 1e-2;
  // The reference's stop, residual acceleration in m/s^2 (1e-2 g; a stop a hundred times finer gives
  // the same rollouts to far below the smallest error a compared method reaches, docs/design.md §6). Also the
  // floor of the forcing term: CG is not asked to reduce the residual below a tenth of what the stop needs.
  double acceleration_tolerance = 0.1;
  int max_cg_iterations = 200;
  // P is refactorized at the current iterate when the last subproblem needed more products
  // with H than this; otherwise its factor is kept, across time steps too when
  // reuse_factor_across_steps (off: a factor per step, the same solve from the same state
  // whatever came before, as meta-training's resumable pool needs).
  int refactor_cg_iterations = 20;
  bool reuse_factor_across_steps = true;
  // P^-1 is applied with a float copy of P's factor (linalg/single_precision_factor.hpp): half
  // the memory traffic of the solves that dominate an iteration on fine grids, the same
  // convergence. From this many entries the copy keeps its values in bfloat16: a factor whose
  // floats do not stay in the caches is read at memory bandwidth, and bfloat16 halves the bytes;
  // smaller factors solve as fast in floats (docs/design.md §6).
  long bfloat16_factor_from_entries = 4000000;
  // On steps with at least this many free dofs, P^-1 is applied approximately, by one V-cycle of a
  // geometric multigrid on P (linalg/block_multigrid.hpp), instead of with P's Cholesky factor:
  // no factorisation and a cheaper product, for more CG iterations: faster on fine grids, as fast
  // on coarse ones (docs/design.md §6). From about 82^2, so that the references of 32^2 and 64^2,
  // where it gains less, stay those of the factor. 0: always. Where
  // a fresh V-cycle leaves CG at max_cg_iterations (very stiff cloth) or cannot be built, the factor
  // takes over for good.
  int multigrid_from_dofs = 20000;
  BlockMultigridParams multigrid;
  // Seek a local minimum of the step's energy instead of any stationary point ("newton-min"):
  // where the stop is met but the exact Hessian has negative eigenvalues (a saddle: its LDL^T
  // factorisation has negative pivots), step along the direction of negative curvature those
  // pivots give and go on (leave_stationary_point). Off for the reference (docs/design.md §6,
  // "What the reference converges to"); at most max_saddle_escapes per time step.
  bool escape_saddles = false;
  int max_saddle_escapes = 50;

  void validate() const;  // throws Error naming the parameter
};

// Work counters, for benchmarks.
struct NewtonCounters {
  long factorizations = 0;       // builds of P's preconditioner: its Cholesky factor or its multigrid levels
  long cg_iterations = 0;        // products with H
  long negative_curvature = 0;   // subproblems that followed a negative-curvature direction
  long rejected_trials = 0;      // trial steps the trust region turned down
  long saddle_escapes = 0;       // steps off a saddle (escape_saddles)
  long multigrid_fallbacks = 0;  // 1 once a fresh V-cycle left CG at its cap or could not be built: the factor since
};

class NewtonOptimizer final : public InnerOptimizer {
 public:
  explicit NewtonOptimizer(NewtonParams params = {});

  // The reference: residual acceleration <= acceleration_tolerance at every free vertex. The cap is
  // generous: the stability suite's stiffest cloth needs more than 200 iterations on some steps
  // (docs/design.md §6).
  static InnerSolveOptions reference_solve_options() { return {1000, 0.0, NewtonParams{}.acceleration_tolerance}; }
  // The reference's stop as help texts and reports state it: "0.1 m/s^2".
  static std::string reference_stop_text();

  std::string name() const override { return params_.escape_saddles ? "newton-min" : "newton"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;
  // With escape_saddles, at a stationary point where the exact Hessian H has negative pivots in its
  // LDL^T factorisation: a moves along -sign(g.z) z, z the direction of negative curvature they
  // give (linalg/matrix_inertia.hpp, Moré & Sorensen 1979), from the trust radius in the mass
  // metric down until L falls. False (a not moved) at a minimum.
  bool leave_stationary_point(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;
  // Each trial is already the feasible part of its step (iterate()).
  bool filters_its_iterates() const override { return true; }

  const NewtonCounters& counters() const { return counters_; }

 private:
  // The trust region's metric on the free dofs, the inertia weights dt^2 m (1 + c dt).
  void set_metric(const StepProblem& problem);
  // Builds the preconditioner from P, the projected Hessian (its factor, or its multigrid levels);
  // false if CHOLMOD fails (P is positive definite by construction).
  bool factorize_preconditioner(StepProblem& problem, const Eigen::SparseMatrix<double>& projected);
  // The multigrid does not serve this rollout: P's factor from the next build on (counted once).
  void hand_over_to_factor();
  Eigen::Index preconditioner_rows() const { return use_multigrid_ ? multigrid_.rows() : factor_.rows(); }
  // Whether P must be rebuilt at this iterate (none yet, another size, the multigrid switched on or
  // off, or the last CG needed too many products); rhs_ holds the free gradient.
  bool preconditioner_is_stale();
  // H at a, for CG's products (valid until the objective's next Hessian), and P rebuilt from the
  // same evaluation of the stencils where `stale`; nullptr where P's factorisation failed.
  const SymmetricBlockMatrix* hessian_and_preconditioner(StepProblem& problem, const VecX& a, bool stale);
  // trial_ = a + s full_step_, the feasible part of the step (s = pullback x its feasible fraction
  // with contact, 1 where all of it is and without contact); returns s.
  double feasible_trial(StepProblem& problem, const VecX& a);
  // The trust region after a trial of ratio actual / predicted decrease, cut to `cut` of CG's step.
  void update_radius(double ratio, double cut, const SteihaugResult& sub);

  NewtonParams params_;
  SparseCholesky factor_;
  SinglePrecisionFactor single_factor_;  // its float copy, which applies P^-1
  BlockMultigrid multigrid_;             // in their place, on steps of multigrid_from_dofs free dofs or more
  bool use_multigrid_ = false;           // this step's choice
  bool multigrid_failed_ = false;        // hand_over_to_factor() was called: the factor from then on
  bool have_factor_ = false;
  int last_cg_iterations_ = 0;
  NewtonCounters counters_;
  double initial_gradient_norm_ = 0.0;
  double start_value_ = 0.0;
  double radius_ = 0.0;  // 0: set at the step's first iteration
  int escapes_ = 0;      // saddle escapes in this time step
  SteihaugScratch cg_;
  SteihaugPath cg_path_;  // the iterate's last CG run, for the trials after a rejected one
  VecX metric_;           // the trust region's: the inertia weights dt^2 m (1 + c dt) of the free dofs
  VecX rhs_, step_, full_step_, trial_, trial_gradient_;
  VecX preconditioned_gradient_;  // P^-1 g at the step's first iteration, which sizes the region and starts CG
};

}  // namespace fnopt
