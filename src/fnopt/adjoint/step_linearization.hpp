#pragma once
// One backward-Euler step linearised at its result (docs/design.md §15): the stationarity
// condition of the step's free dofs F,
//   g_F(a; x_t, v_t, a_H, theta) = 0,
//   g_k = dt^2 [m_k (a_k - gravity) + grad P(x)_k + (c m_k / dt)(x_k - x_t,k)],   x = x_t + dt v_t + dt^2 a,
// and its derivatives at the step's acceleration a: the exact (unprojected) Hessian
// H = dt^2 M (1 + c dt) + dt^4 K, K = hess P, factorised on F, and the products the adjoint needs,
//   dg/dx_t = dt^2 K,   dg/dv_t = dt^3 K + dt^2 c M,   dg/da_H = dt^4 K_(.,H),
//   dg/dk = dt^2 grad P_k(x) / k  (stretch, shear, bend: each term is linear in its stiffness),
//   dg/drho = dt^2 A_k [(a_k - gravity) + (c/dt)(x_k - x_t,k)]   (m_k = rho A_k),
//   dg/dc = dt m_k (x_k - x_t,k),   dg/dgravity = -dt^2 m_k I.
// Self-repulsion's pairs are those begin_step freezes from x_t and x_t + dt v_t, as in the
// forward step: the same pairs, so the same smooth energy, differentiated with the pairs fixed.
// Contact (docs/design.md §14): the barrier is part of P; the lagged friction D(x; x_t) is too, and
// depends on x_t also through its frozen normal force, tangent plane and start, so that
//   dg/dx_t = dt^2 (K + J),   J = d(grad_x D)/dx_t at fixed x   (ContactTerm::add_friction_start_product,
//   MeshContactTerm::, SelfContactTerm::add_friction_start_product).
//
// H_FF is factorised as a matrix over every dof whose handle rows and columns are replaced by the
// handles' inertia weights on the diagonal (the same sparsity pattern at every step, so the
// symbolic analysis is reused while the repulsion pattern holds): its Cholesky factor exists iff
// H_FF is positive definite. Where it does not, an LDL^T factorisation without pivoting (AMD
// ordering) says whether the step ended at a saddle (negative pivots: as many as H_FF has negative
// eigenvalues, Sylvester) or at a singular point (a pivot that vanishes against the largest),
// and at a saddle solves with it.
#include <Eigen/SparseCholesky>
#include <memory>
#include <vector>

#include <fnopt/adjoint/material_gradient.hpp>
#include <fnopt/linalg/sparse_cholesky.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// What the exact Hessian of a step's free dofs is at the step's result.
enum class StepStationarity {
  Minimum,   // positive definite: a strict local minimum, the implicit function theorem applies
  Saddle,    // non-singular with negative eigenvalues: the step's branch is still differentiable
  Singular,  // a vanishing pivot: the step's result does not depend smoothly on its inputs
};
const char* to_string(StepStationarity stationarity);

class StepLinearization {
 public:
  // The objective of the resolved scene (its material, dt and gravity) and, for the stiffness
  // derivatives, the stretch, shear and bend terms at unit stiffness.
  explicit StepLinearization(const ResolvedScene& scene);

  // Linearises the step from (x, v) at time t at its acceleration a (every dof, the handles'
  // prescribed; the time poses the obstacles): assembles H at a, factorises H_FF, and returns what
  // it is there.
  StepStationarity linearize(const VecX& x, const VecX& v, const VecX& a, double time);
  // H_FF's negative eigenvalues after linearize(): 0 at a minimum, -1 where singular.
  int negative_eigenvalues() const { return negative_eigenvalues_; }

  // lambda = H_FF^-1 rhs_F, zero on the handles' dofs (rhs's are ignored). Not after a Singular.
  void solve(const VecX& rhs, VecX& lambda);
  // dt^4 K lambda over every dof, for lambda zero on the handles: the product with H less the
  // inertia's diagonal. It is lambda^T dg/da (= dg/da_H on the handles), dt^2 times dg/dx_t's.
  void stiffness_product(const VecX& lambda, VecX& product) const;
  // Subtracts dt^2 J^T lambda, the lagged friction's part of lambda^T dg/dx_t beyond dt^2 K lambda,
  // from xbar (nothing without friction).
  void subtract_friction_start_product(const VecX& lambda, VecX& xbar);
  // -lambda^T dg_F/dtheta at the linearised step, for lambda zero on the handles.
  MaterialGradient material_gradient(const VecX& lambda);

  // Carries a tangent (dx, dv) of the step's start state, and of parameters whose g_F changes by
  // `source` (or none), through the linearised step: the free accelerations solve
  //   H_FF da_F = -[dt^2 K z + dt^2 c M dv + source]_F,   z = dx + dt dv (zero on the held handles),
  // the held handles' da_H = -(dx + dt dv)_H / dt^2 keeps them on their targets, and then
  //   dx <- dx + dt dv + dt^2 da,   dv <- dv + dt da
  // (the derivative of g_F = 0 along the tangent; the lagged friction's dependence on the step's
  // start is left out). Not after a Singular.
  void advance_tangent(VecX& dx, VecX& dv, const VecX* source);
  // k dg/dk over every dof for a material coefficient k (is_material_coefficient): g_F's change per
  // unit change of ln k at the linearised step, the source of a tangent along ln k.
  void log_material_derivative(AdjointParameter coefficient, VecX& out);

  // dt^2 d^3P(x)[t, t] over every dof at the linearised step's result x, for a move t of the
  // positions [m]: the second-order term of g's change along t (every other term of g is linear in
  // x), by the second difference of grad L along t, its move scaled to `probe` metres:
  //   |t|^2 (grad L(a + h u) + grad L(a - h u) - 2 grad L(a)) / h^2,   u = t / (|t| dt^2),  h = probe.
  void third_derivative(const VecX& t, double probe, VecX& out);

  // The linearised step's damping-weighted mass of vertex k, dt^2 c m_k, the part of dg/dv_t that
  // is not dt K.
  double damping_weight(int k) const { return objective_.dt() * objective_.dt() * material_.damping * masses_[k]; }
  // The scene's handles let go (Scene::let_go): from the next linearize() on, every vertex is free.
  void set_released(bool released);
  const BackwardEulerObjective& objective() const { return objective_; }

  long factorizations() const { return factorizations_; }  // Cholesky and LDL^T
  long solves() const { return solves_; }

 private:
  Material material_;
  BackwardEulerObjective objective_;
  std::vector<std::unique_ptr<EnergyTerm>> unit_terms_;  // stretch, shear, bend at stiffness 1
  std::vector<int> scene_handles_;                       // the scene's handle vertices
  std::vector<int> handle_vertices_;                     // those held at this step: the scene's, none once released
  std::vector<char> handle_vertex_;
  bool released_ = false;
  std::vector<int> all_free_;                             // every vertex free: H over every dof
  VecX masses_, areas_;                                   // m_k and A_k = m_k / rho
  VecX x_, x_start_, a_;                                  // the linearised step's x_{t+1}, x_t and a
  const Eigen::SparseMatrix<double>* hessian_ = nullptr;  // H over every dof, the objective's
  Eigen::SparseMatrix<double> masked_;                    // H_FF with the handles' inertia on their diagonal
  long masked_pattern_ = -1;
  SparseCholesky cholesky_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt_;
  long ldlt_pattern_ = -1;  // the pattern ldlt_ analysed last
  bool use_ldlt_ = false;
  int negative_eigenvalues_ = 0;
  VecX gradient_buffer_, friction_buffer_, probe_a_, probe_gradient_, tangent_z_, tangent_rhs_, tangent_a_;
  long factorizations_ = 0;
  long solves_ = 0;
};

}  // namespace fnopt
