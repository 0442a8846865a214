#pragma once
// The meta-training loss of fnopt-pqn's probe (docs/design.md §13): how close pqn's next
// iteration comes to the Newton step once it holds the curvature pair measured along a
// proposal p. On the local quadratic model of L at a,
//   m(d) = g.d + d.H d / 2   (g the masked gradient, H the Hessian, each stencil projected to PSD),
// the probe is the pair s = alpha p, alpha = -g.p / p.A p, y = H s, and pqn's iteration is the
// two-loop recursion over it on A^-1 (baselines/pqn.hpp):
//   rho = 1 / s.y,  c = rho s.g,  r = A^-1 (g - c y),  d = -(r + s (c - rho y.r)).
// The loss is the remaining fraction of the model's decrease,
//   R(p) = 1 - m(d(p)) / m*,   m* = -g.H^-1 g / 2 (the Newton step's),
// 0 where p points along the Newton step (the pair then makes d the Newton step), and R0 =
// 1 - m(-A^-1 g) / m* for pqn's own first iteration without a probe. R is invariant to the
// scale and sign of p, as the probe is. It is differentiable in p through LibTorch, the three
// symmetric operators (H, A, A^-1) entering as custom autograd functions, so the energy is still
// written once, in cloth/.
#include <torch/torch.h>

#include <memory>

#include "baselines/pqn_matrix.hpp"
#include "optimizer/sparse_cholesky.hpp"
#include "optimizer/step_problem.hpp"

namespace fnopt {

class ProbeLoss {
 public:
  // The model at a, with `gradient` the masked gradient there (StepProblem::value_gradient) and
  // pqn's matrix of `kind` for the problem's time step. Throws Error if H or A is not positive
  // definite.
  ProbeLoss(StepProblem& problem, const VecX& a, const VecX& gradient,
            PqnMatrixKind kind = PqnMatrixKind::Isotropic);
  ~ProbeLoss();
  ProbeLoss(const ProbeLoss&) = delete;  // the autograd graph points into it
  ProbeLoss& operator=(const ProbeLoss&) = delete;

  // False where a is already the model's minimum (g = 0): R is then undefined.
  bool defined() const { return newton_decrease_ < 0.0; }

  // R(p) (needs defined()) for p on the free dofs (3 per free vertex, the Hessian's layout),
  // float64 [3 n_free].
  torch::Tensor remaining(const torch::Tensor& p) const;
  // R0: pqn's first iteration without a probe.
  double remaining_without_probe() const { return remaining_without_probe_; }

  // p in this layout from a per-vertex field of 3 dofs ([3, 1, R, C] coordinate samples, the
  // learned optimizer's layout; differentiable).
  torch::Tensor free_dofs(const torch::Tensor& coordinate_samples) const;
  // The masked gradient at a on the free dofs.
  const VecX& gradient() const { return gradient_; }

 private:
  struct Maps;  // H, A and A^-1 as the autograd functions apply them
  std::unique_ptr<Maps> maps_;
  VecX gradient_;
  Eigen::SparseMatrix<double> hessian_, matrix_;  // H and A on the free dofs
  mutable SparseCholesky matrix_factor_;  // A's (A^-1 in the graph)
  torch::Tensor free_dof_index_;  // free dof k -> its index among the 3 R C dofs
  double newton_decrease_ = 0.0;  // m* (negative)
  double remaining_without_probe_ = 0.0;
};

}  // namespace fnopt
