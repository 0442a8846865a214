#pragma once
// L-BFGS (Nocedal 1980; docs/design.md §6) in the mass metric of first_order.hpp: the two-loop
// recursion over the last `history` curvature pairs (s, y) with the initial inverse Hessian
// H0 = gamma P^-1, gamma = s.y / (y.P^-1 y) of the newest pair (the Shanno-Phua scaling, in the
// metric P = dt^2 M, so a cloth step starts from the inertia-only exact step).
//
// Two variants (the `line_search` flag):
//  - fixed step (the paper's, "lbfgs"): a <- a + d, no line search, as torch.optim.LBFGS with
//    lr = 1 and line_search_fn = None: the first iteration of a time step has no pairs and steps
//    t0 = min(1, 1/||P^-1 g||_1) along -P^-1 g, which only probes the curvature; a pair with
//    s.y <= 0 is skipped. Nothing stops it from overshooting on a stiff or non-convex step.
//  - line search ("lbfgs-ls", the fair one): the strong-Wolfe line search of
//    optimizer/line_search.hpp (c1 = 1e-4, c2 = 0.9) with the trial step 1 (on the first
//    iteration the inertia-only step -P^-1 g). Every accepted step satisfies s.y > 0, so the
//    history stays positive definite.
// The history is cleared at every time step (begin()). Iterations count outer iterations:
// a line-search iteration costs one gradient evaluation per trial (usually one).
#include <vector>

#include <fnopt/baselines/curvature_history.hpp>
#include <fnopt/baselines/first_order.hpp>
#include <fnopt/optimizer/line_search.hpp>

namespace fnopt {

struct LbfgsParams {
  int history = 5;           // curvature pairs kept (m)
  bool line_search = false;  // false: fixed step 1 (the paper's); true: strong Wolfe
  WolfeParams wolfe;         // of the line search: c1 1e-4, c2 0.9, 20 evaluations
  void validate() const;     // throws Error naming the parameter
};

class LbfgsOptimizer final : public FirstOrderOptimizer {
 public:
  explicit LbfgsOptimizer(LbfgsParams params = {});

  std::string name() const override { return params_.line_search ? "lbfgs-ls" : "lbfgs"; }
  std::string settings() const override;
  void begin(SmoothProblem& problem, const VecX& x, double value, const VecX& gradient) override;
  std::optional<SolveStatus> step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) override;

  long skipped_pairs() const { return skipped_pairs_; }          // s.y <= 0: not stored
  long line_search_evaluations() const { return evaluations_; }  // trials, all steps

 private:
  // Sets direction_ (a descent direction) and the first trial step.
  double compute_direction(SmoothProblem& problem, const VecX& gradient);
  void remember(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new, const VecX& inverse_metric);

  LbfgsParams params_;
  CurvatureHistory history_;
  std::vector<double> alphas_;
  VecX direction_, h0_, x_old_, g_old_;
  WolfeScratch line_search_;
  long skipped_pairs_ = 0;
  long evaluations_ = 0;
};

}  // namespace fnopt
