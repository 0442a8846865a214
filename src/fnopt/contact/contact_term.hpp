#pragma once
// Contact of the cloth's vertices with analytic obstacles (docs/design.md §14): an EnergyTerm of
// the backward-Euler objective, built only when a scene has obstacles.
//
// Barrier. Per vertex i and obstacle k, on the gap g = d_k(x_i) - thickness with the obstacle at
// its pose at the step's END t + dt, the self-repulsion's log barrier (§2, repulsion_kernel.hpp):
//   b(g) = -kappa (g - dhat)^2 log(g / dhat)   (0 < g < dhat),   0 (g >= dhat),   +inf (g <= 0).
// grad = b'(g) n and hess = b''(g) n n^T + b'(g) hess d, n = grad d. b' < 0 inside the range and
// hess d is positive semi-definite outside a convex shape (obstacle.hpp), so the second part is
// the only indefinite one; projected, it becomes |b'(g)| hess d.
// Friction. IPC's lagged friction (friction.hpp): the pairs within range at x_t, each with its
// normal force lambda = -b'(g(x_t)) at the pose of the step's START, frozen in begin_step.
//
// Broad phase: linear in the vertex count. Per evaluation the cloth's bounding box is tested
// against each obstacle's box grown by thickness + dhat; an obstacle that passes is tested at each
// vertex by its closed-form distance. The energy is exact for every vertex and obstacle: no pair
// is frozen except friction's. The Hessian adds one 3x3 block per vertex (its diagonal block, always
// in the pattern), so the pattern never changes.
#include <string>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/contact/contact_params.hpp>
#include <fnopt/contact/friction.hpp>
#include <fnopt/contact/obstacle.hpp>

namespace fnopt {

// The obstacles' translations from their rest poses at a step's start and end, one per obstacle.
struct ObstacleOffsets {
  std::vector<Vec3> start, end;
};

class ContactTerm final : public EnergyTerm {
 public:
  static constexpr long kParallelThreshold = 2048;

  // dhat = params.range_fraction * grid.h. Throws Error naming a bad parameter or an empty list.
  ContactTerm(const Grid& grid, std::vector<Obstacle> obstacles, const ContactParams& params);

  // Poses the obstacles for the step from `time` to `time + dt` and freezes the friction pairs at
  // the start positions. The poses are the obstacles' motions at both times, or `offsets`: each
  // obstacle's translation from its rest pose at the step's start and end (a caller steering them).
  void begin_step(const VecX& x_start, double time, double dt, const ObstacleOffsets* offsets = nullptr);

  const std::string& name() const override { return name_; }
  // The barrier and the friction potential: the step's objective.
  double energy(const VecX& x) const override;
  // The barrier alone: the potential energy of a state (the friction potential is the step's
  // dissipation, not an energy the state holds).
  double barrier_energy(const VecX& x) const;
  double accumulate_gradient(const VecX& x, VecX& grad) const override;
  int register_hessian(HessianAssembly& assembly) const override;
  void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const override;

  // The largest s in [0, 1] such that no vertex that moves comes within the thickness of an
  // obstacle (at the step's end pose) on the straight path from x_from to x_to before s (ccd.hpp).
  double safe_fraction(const VecX& x_from, const VecX& x_to) const;
  // The same, given a box [lower, upper] that holds every vertex of both states (a caller that has
  // bounded them already: the box is not computed again).
  double safe_fraction(const VecX& x_from, const VecX& x_to, const Vec3& lower, const Vec3& upper) const;
  // Whether some obstacle (at the step's end pose) may come within the thickness of a point in the
  // box [lower, upper]; where none may, every straight path inside the box is safe (the broad
  // phase of safe_fraction, for a caller that bounds the paths more cheaply than by their ends).
  bool may_touch(const Vec3& lower, const Vec3& upper) const;
  // The lagged friction's dependence on the step's start, for the adjoint (docs/design.md §15):
  // adds J_i^T lambda_i to out_i for each friction pair's vertex i, J_i = d(grad_x D_i)/dx_t,i at x,
  // through the frozen normal force, tangent plane and start (friction.hpp):
  //   grad_x D = W phi(y) z,  W = -mu b'(g(x_t)),  z = P w,  P = I - n n^T,  n = grad d(x_t),
  //   w = x - x_t - Delta o,  phi = f1/y,  y = |z|,  J_psi = phi I + (phi'/y) z z^T,
  //   J = -mu b''(g) phi z n^T  -  W J_psi P  -  W J_psi ((n.w) I + n w^T) hess d(x_t),
  // the middle term being -hess_x D.
  void add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const;
  // Start positions the step's solve can begin from: x_t, except that a vertex an obstacle would
  // sweep over during the step (the vertex held still, the obstacle translating) moves with that
  // obstacle, x_t + Delta o. Written to `x_safe`.
  void safe_start_positions(const VecX& x_start, VecX& x_safe) const;

  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  const ContactParams& params() const { return params_; }
  double range() const { return kernel_.range; }  // dhat [m]
  double thickness() const { return params_.thickness; }
  // The obstacle's translation at the step's start and end.
  const Vec3& start_offset(int k) const { return start_offsets_[k]; }
  const Vec3& end_offset(int k) const { return end_offsets_[k]; }
  const std::vector<FrictionPair>& friction_pairs() const { return friction_pairs_; }

 private:
  // Whether obstacle k, at its step's end, may come within `reach` of a point in the box [lower,
  // upper]: its own box grown by reach meets it, or for a plane the box's lowest corner along the
  // normal is within reach. A conservative test (the broad phase, docs/design.md §14).
  bool may_reach(std::size_t k, const Vec3& lower, const Vec3& upper, double reach) const;
  // near_[k]: whether obstacle k may reach the box of x within thickness + dhat; true if any may
  // (else the barrier is zero at x, with its derivatives, and no vertex need be visited).
  bool mark_near_obstacles(const VecX& x) const;
  // The barrier energy of a vertex at p against the near obstacles (+inf within the thickness of
  // one); adds its gradient and Hessian where given.
  double vertex_barrier(const Vec3& p, Vec3* gradient, Mat3* hessian, bool project) const;

  std::string name_ = "contact";
  int vertex_count_;
  std::vector<Obstacle> obstacles_;
  ContactParams params_;
  RepulsionKernel kernel_;  // the scalar barrier b(g) with kappa and dhat
  FrictionMollifier mollifier_;
  std::vector<Vec3> start_offsets_, end_offsets_;
  std::vector<Vec3> lower_, upper_;  // obstacles' boxes at rest
  std::vector<FrictionPair> friction_pairs_;
  std::vector<int> vertices_;  // 0..n-1, the one-vertex stencils of the Hessian
  mutable std::vector<char> near_;
};

}  // namespace fnopt
