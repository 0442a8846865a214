#pragma once
// The Newton reference solve (DESIGN.md §6): it defines the exact backward-Euler step of the
// energy, the ground truth of every error fnopt reports.
//   d = -H^{-1} g  (sparse Cholesky, Eigen SimplicialLLT, AMD ordering analysed once),
//   a <- a + alpha d with backtracking until Armijo's condition holds,
// until ||g|| <= relative_tolerance * ||g_0|| over the free dofs. H is the exact Hessian while
// it is positive definite (quadratic convergence); the first time Cholesky finds it is not,
// the solve switches to the projected Hessian (per-stencil PSD projection, Teran et al. 2005)
// for the rest of the step.
#include <Eigen/SparseCholesky>

#include "boundary/dirichlet.hpp"
#include "cloth/backward_euler.hpp"
#include "optimizer/solve_status.hpp"

namespace fnopt {

struct NewtonParams {
  double relative_tolerance = 1e-9;  // stop at ||g|| <= tol * ||g_0||
  int max_iterations = 100;
  double armijo = 1e-4;              // sufficient-decrease constant c1
  double backtrack = 0.5;            // step shrink factor per line-search trial
  int max_backtracks = 40;
  bool exact_hessian_first = true;   // false: always project (plain projected Newton)

  void validate() const;  // throws Error naming the parameter
};

struct NewtonResult {
  SolveStatus status = SolveStatus::IterationBudget;
  int iterations = 0;
  int projected_iterations = 0;  // iterations that used the projected Hessian
  double initial_gradient_norm = 0.0;
  double gradient_norm = 0.0;
  double value = 0.0;
  std::vector<double> gradient_norms;  // ||g|| at each iterate, the first being ||g_0||
};

class NewtonSolver {
 public:
  explicit NewtonSolver(NewtonParams params = {});

  // Minimises objective.value over the free dofs of `a`, starting from `a` (whose fixed dofs
  // hold the prescribed handle accelerations and are not changed).
  NewtonResult solve(BackwardEulerObjective& objective, const DirichletSet& dirichlet, VecX& a);

 private:
  bool factorize(const Eigen::SparseMatrix<double>& H);

  NewtonParams params_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
  const void* analysed_pattern_ = nullptr;
  VecX grad_, trial_, trial_grad_, reduced_grad_, reduced_trial_grad_, direction_;
};

}  // namespace fnopt
