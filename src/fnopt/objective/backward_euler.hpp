#pragma once
// The backward-Euler objective of one time step (docs/design.md §2). Unknown: the acceleration a.
//   v(a) = v_t + dt a,   x(a) = x_t + dt v(a) = x^ + dt^2 a,   x^ = x_t + dt v_t,
//   L(a) = sum_i m_i/2 dt^2 |a_i|^2 + P(x(a)) [+ sum_i c m_i/(2 dt) |x_i(a) - x_t,i|^2],
// whose minimiser is the implicit-Euler step. The gradient and Hessian w.r.t. a are
//   grad L = dt^2 (M a + grad P(x)),   hess L = dt^2 M + dt^4 hess P(x).
// Gravity, -sum_i m_i g.x_i, is linear: it enters L as -dt^2 sum_i m_i g.a_i, i.e. relative to
// x^. Dropping the constant -sum_i m_i g.x^ changes no minimiser, gradient or difference of
// values, but keeps L small: otherwise the gravity potential (~1 J) would dominate L and hide
// decreases below ~1e-16 J from the line search.
// Self-repulsion (material.repulsion) freezes its pairs at begin_step (repulsion_term.hpp); when
// that changes its Hessian pattern, the next hessian() builds a new sparse matrix with a new
// hessian_pattern_id(), unique across all objectives of the process, so a cache keyed on it,
// like NewtonOptimizer's symbolic analysis, sees every pattern change.
// Obstacles (docs/design.md §14) add the contact term (contact/contact_term.hpp) for the analytic
// ones and the mesh contact term (contact/mesh_contact_term.hpp) for the meshes, each built only
// when there are such obstacles, and self-contact its term, built only where the scene enables it:
// without them the objective is the same code and arithmetic as before.
// Not thread-safe: evaluation reuses internal buffers (no allocation per call).
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/cloth/material.hpp>
#include <fnopt/contact/contact_params.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/contact/self_contact_params.hpp>

namespace fnopt {

class ContactTerm;
class MeshContactTerm;
struct ObstacleOffsets;
class RepulsionTerm;
class SelfContactTerm;

class BackwardEulerObjective {
 public:
  BackwardEulerObjective(const Grid& grid, const Material& material, double dt, const Vec3& gravity);
  // With obstacles: the contact term for the analytic ones and the mesh contact term for the meshes,
  // each where there is one; with `self_contact`, the self-contact term
  // (contact/self_contact_term.hpp).
  BackwardEulerObjective(const Grid& grid, const Material& material, double dt, const Vec3& gravity,
                         std::vector<Obstacle> obstacles, const ContactParams& contact = {},
                         const std::optional<SelfContactParams>& self_contact = std::nullopt);

  const Grid& grid() const { return grid_; }
  // What the objective was built from (an optimizer may build the same step on another grid).
  const Material& material() const { return material_; }
  const Vec3& gravity() const { return gravity_; }
  double dt() const { return dt_; }
  const VecX& masses() const { return masses_; }  // per vertex
  // The inertia (and damping) part of hess L on vertex k's three dofs: dt^2 m_k (1 + c dt).
  double inertia_weight(int k) const { return dt_ * dt_ * masses_[k] * (1.0 + damping_ * dt_); }
  const std::vector<std::unique_ptr<EnergyTerm>>& terms() const { return terms_; }
  // The self-repulsion term, or null when the material does not enable it.
  const RepulsionTerm* repulsion() const { return repulsion_; }
  // The contact term, or null without analytic obstacles.
  const ContactTerm* contact() const { return contact_; }
  // The mesh contact term, or null without mesh obstacles.
  const MeshContactTerm* mesh_contact() const { return mesh_contact_; }
  // The self-contact term, or null where self-contact is off.
  const SelfContactTerm* self_contact() const { return self_contact_; }
  // Changes whenever hessian() builds a new sparsity pattern; unique across objectives.
  long hessian_pattern_id() const { return pattern_id_; }

  // Starts a step from positions x_t and velocities v_t at time t [s] (freezes the repulsion pairs;
  // poses the obstacles at t and t + dt, on their motions or at `obstacle_offsets`, and freezes
  // their friction pairs).
  void begin_step(const VecX& x, const VecX& v, double time = 0.0, const ObstacleOffsets* obstacle_offsets = nullptr);
  double start_time() const { return time_; }
  const VecX& start_positions() const { return x_start_; }
  const VecX& start_velocities() const { return v_start_; }

  // x(a) = x^ + dt^2 a.
  void trial_positions(const VecX& a, VecX& x) const { x.noalias() = x_inertial_ + dt_ * dt_ * a; }
  const VecX& inertial_positions() const { return x_inertial_; }  // x^ = x_t + dt v_t
  double value(const VecX& a) const;
  // Writes grad L(a) (every dof, handles included: masking is the caller's) and returns L(a).
  double value_gradient(const VecX& a, VecX& grad) const;

  // max_i |g_i| / (m_i dt^2) over the dofs of a gradient g of L: since g = dt^2 (M a - f(x)),
  // the acceleration (m/s^2) that the forces leave unbalanced at a. Zero exactly at a stationary
  // point, in the same unit at every resolution.
  double residual_acceleration(const VecX& gradient) const;

  // hess L(a) restricted to the free vertices (free_index[v] >= 0), each stencil projected to
  // PSD if `project`. The sparsity pattern is built on the first call for a given free set.
  const Eigen::SparseMatrix<double>& hessian(const VecX& a, const std::vector<int>& free_index, bool project);
  // The same matrix as its lower triangle of 3x3 blocks, for products: half of hessian()'s writes
  // (the Newton reference's exact Hessian at every iteration). Valid until the next hessian call.
  const SymmetricBlockMatrix& hessian_blocks(const VecX& a, const std::vector<int>& free_index, bool project);
  // hessian_blocks(a, free_index, false) and hessian(a, free_index, true), the same values, from one
  // evaluation of each stencil (the Newton reference's iterations that rebuild its preconditioner).
  // Both valid until the next hessian call.
  struct HessianPair {
    const SymmetricBlockMatrix& exact;
    const Eigen::SparseMatrix<double>& projected;
  };
  HessianPair hessian_pair(const VecX& a, const std::vector<int>& free_index);

  // The potential P(x) (elastic + gravity, zero at height 0; with obstacles their barrier, not the
  // step's friction potential) and the kinetic energy of v.
  double potential(const VecX& x) const;
  double kinetic(const VecX& v) const;

 private:
  const HessianAssembly& assemble_hessian(const VecX& a, const std::vector<int>& free_index, bool project,
                                          HessianAssembly::Target target);

  Grid grid_;
  Material material_;
  double dt_;
  double damping_;
  Vec3 gravity_;
  VecX masses_;
  std::vector<std::unique_ptr<EnergyTerm>> terms_;
  VecX x_start_, v_start_, x_inertial_;
  mutable VecX x_trial_, grad_x_;
  std::vector<int> hessian_free_index_;
  std::unique_ptr<HessianAssembly> assembly_;
  std::vector<int> term_handles_;
  RepulsionTerm* repulsion_ = nullptr;  // one of terms_
  ContactTerm* contact_ = nullptr;      // one of terms_
  MeshContactTerm* mesh_contact_ = nullptr;  // one of terms_
  // The scene's obstacle index of each analytic obstacle and each mesh, in the terms' order.
  std::vector<int> analytic_index_, mesh_index_;
  SelfContactTerm* self_contact_ = nullptr;  // one of terms_
  double time_ = 0.0;
  // The pattern generations (repulsion's, self-contact's) assembly_ was built for.
  std::pair<long, long> assembled_generation_{-1, -1};
  long pattern_id_ = 0;
};

}  // namespace fnopt
