#pragma once
// Prefactored quasi-Newton ("pqn"; Liu, Bouaziz & Kavan 2017, "Quasi-Newton methods for
// real-time simulation of hyperelastic materials"): L-BFGS whose initial inverse Hessian is
// A^-1, A a fixed matrix close to the Hessian of a cloth step (baselines/pqn_matrix.hpp: the
// inertia exactly, the elastic part as an isotropic, rotation-invariant projective-dynamics
// matrix), factorised once per scene. Each iteration:
//   d = -H g by the two-loop recursion over the last `history` pairs on H0 = A^-1 (one pair of
//       triangular solves with A's Cholesky factor),
//   a <- a + t d, t from 1 by backtracking (optimizer/line_search.hpp),
// one gradient evaluation per trial (usually one). Without pairs (the first iteration of a
// step) d = -A^-1 g, which is the exact step where the elastic energy is as A says: the cloth
// at rest, or any quadratic whose Hessian is A. Why it beats a diagonal H0 on cloth: A carries
// the stiff spring couplings that make L-BFGS's diagonal start overshoot (docs/design.md).
//
// The factor is refactorised only when what A depends on changes (PqnFactorCache). The history
// is cleared at every time step.
#include <optional>
#include <string>
#include <vector>

#include <fnopt/baselines/curvature_history.hpp>
#include <fnopt/baselines/first_order.hpp>
#include <fnopt/baselines/pqn_matrix.hpp>
#include <fnopt/optimizer/line_search.hpp>

namespace fnopt {

struct PqnParams {
  int history = 5;  // curvature pairs kept (m); 0: every iteration steps along -A^-1 g
  BacktrackingParams line_search{1e-4, 0.5, 30};

  void validate() const;  // throws Error("pqn.<parameter>: ...")
};

class PqnOptimizer final : public FirstOrderOptimizer {
 public:
  explicit PqnOptimizer(PqnParams params = {});

  std::string name() const override { return "pqn"; }
  std::string settings() const override;
  void begin(SmoothProblem& problem, const VecX& x, double value, const VecX& gradient) override;
  std::optional<SolveStatus> step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) override;

  // For problems that are not cloth steps (tests, tools): factorizes `matrix` and uses it on
  // every such problem. Throws Error if it is not positive definite.
  void use_matrix(const PqnMatrix& matrix);
  // Adds the curvature pair of a step taken by someone else (x_old -> x_new with gradients
  // g_old, g_new) to this time step's history, under the same positivity test as pqn's own
  // pairs; returns whether it was kept. The hybrid with the learned optimizer feeds its
  // proposals this way (learned/learned_pqn.hpp).
  bool add_pair(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new);
  // The factor of A for the problem of the current time step (after begin_step).
  PqnFactor& factor() const;
  // Factorizations of A so far (one per scene; tests).
  long factorizations() const { return cache_.factorizations() + given_factorizations_; }

 private:
  PqnParams params_;
  PqnFactorCache cache_;
  PqnFactor given_;  // use_matrix()'s
  long given_factorizations_ = 0;
  PqnFactor* factor_ = nullptr;  // the factor of the problem at hand
  CurvatureHistory history_;
  double start_value_ = 0.0;
  VecX direction_, x_old_, g_old_;
  std::vector<double> alphas_;
  LineSearchScratch line_search_;
};

}  // namespace fnopt
