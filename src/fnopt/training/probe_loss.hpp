#pragma once
// The meta-training loss of fnopt-pqn's probe (docs/design.md §13): how close pqn's next K
// iterations come to the step's solution once they hold the curvature pair measured along a
// proposal p. The probe is the pair s = alpha p, alpha = -g.p / p.A p (A pqn's matrix, g the
// masked gradient at a), y = g(a + s) - g(a), and pqn's iterations run from a as
// baselines/pqn.cpp runs them: the two-loop recursion over the history (the probe's pair first)
// on A^-1, Armijo backtracking from the unit step, each step's pair kept if s.y > 0. They run on
// one of two surfaces f (ProbeSurface):
//   - the step's quadratic model at a, f(d) = g.d + d.H d / 2 (H the Hessian, each stencil
//     projected to PSD), whose minimum f* = -g.H^-1 g / 2 is the Newton step's. With K = 1 the
//     iteration is rho = 1 / s.y, c = rho s.g, r = A^-1 (g - c y), d = -(r + s (c - rho y.r));
//   - the step's energy itself, f(d) = L(a + d), with f* = L(a*) at the Newton solution a*:
//     the loss is then the per-step error (docs/design.md §8) of fnopt-pqn with K iterations.
// The loss is the remaining fraction of the decrease after K iterations,
//   R(p) = (f(d_K(p)) - f*) / (f(0) - f*),
// 0 on the quadratic model where p points along the Newton step (the pair then makes the first
// iteration the Newton step), and R0 the same without a probe (pqn alone). R is invariant to the
// scale and sign of p, as the probe is. It is differentiable in p through LibTorch (the
// backtracking's step lengths are piecewise constant in p): H, A, A^-1 and the energy's gradient
// enter as custom autograd functions with symmetric Jacobians (the energy's: its Hessian,
// unprojected, assembled in the backward pass), so the energy is still written once, in cloth/.
#include <torch/torch.h>

#include <memory>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

// What pqn's iterations run on in the probe loss.
enum class ProbeSurface {
  QuadraticModel,  // the step's quadratic model at a (projected Hessian): three solves per iteration in the graph
  Energy           // the step's energy: a gradient per iteration, a Hessian per iteration in the backward pass
};

struct ProbeLossOptions {
  int iterations = 1;  // K: pqn's iterations after the probe that R scores, in [1, 100]
  ProbeSurface surface = ProbeSurface::QuadraticModel;
  PqnParams pqn;  // pqn's matrix, history and line search, as fnopt-pqn runs it

  void validate() const;  // throws Error("probe.<parameter>: ...")
};

class ProbeLoss {
 public:
  // The loss at a, with `gradient` the masked gradient there (StepProblem::value_gradient).
  // `solution` is the step's Newton solution a*, needed for the Energy surface. Throws Error if
  // A (or, on the quadratic model, H) is not positive definite. The problem's objective and
  // handles must outlive the loss and stay at this time step until its backward pass.
  ProbeLoss(const StepProblem& problem, const VecX& a, const VecX& gradient, const ProbeLossOptions& options = {},
            const VecX* solution = nullptr);
  ~ProbeLoss();
  ProbeLoss(const ProbeLoss&) = delete;  // the autograd graph points into it
  ProbeLoss& operator=(const ProbeLoss&) = delete;

  // False where there is no decrease left to measure (f(0) <= f*): R is then undefined.
  bool defined() const { return start_gap_ > 0.0; }

  // R(p) (needs defined()) for p on the free dofs (3 per free vertex, the Hessian's layout),
  // float64 [3 n_free].
  torch::Tensor remaining(const torch::Tensor& p) const;
  // R0: pqn's K iterations without a probe.
  double remaining_without_probe() const { return remaining_without_probe_; }

  // p in this layout from a per-vertex field of 3 dofs ([3, 1, R, C] coordinate samples, the
  // learned optimizer's layout; differentiable).
  torch::Tensor free_dofs(const torch::Tensor& coordinate_samples) const;
  // The masked gradient at a on the free dofs.
  const VecX& gradient() const { return gradient_; }

 private:
  struct Maps;  // H, A, A^-1 and the energy's gradient as the autograd functions apply them
  // f(d_K) after pqn's K iterations from d = 0, starting from the pair along s if s is defined.
  torch::Tensor surface_after_pqn(const torch::Tensor& s) const;
  // f(d) in double, for the line search.
  double surface_value(const VecX& d) const;
  // a + d on every dof, d on the free dofs.
  VecX at(const VecX& d) const;

  mutable StepProblem problem_;
  ProbeLossOptions options_;
  std::unique_ptr<Maps> maps_;
  VecX a_, gradient_;
  std::vector<Eigen::Index> free_dofs_;                            // free dof k -> its index among the 3 R C dofs
  Eigen::SparseMatrix<double> hessian_, matrix_;                   // H (quadratic model) and A on the free dofs
  mutable SparseCholesky matrix_factor_;                           // A's (A^-1 in the graph)
  torch::Tensor free_dof_index_;                                   // free_dofs_ as a tensor
  double start_value_ = 0.0, best_value_ = 0.0, start_gap_ = 0.0;  // f(0), f*, f(0) - f*
  double remaining_without_probe_ = 0.0;
};

}  // namespace fnopt
