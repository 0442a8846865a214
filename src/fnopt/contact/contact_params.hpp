#pragma once
// The settings of contact with obstacles (docs/design.md §14), each with its unit.
#include <string>

namespace fnopt {

struct ContactParams {
  // kappa [N/m]: the barrier's stiffness, b(g) = -kappa (g - dhat)^2 log(g/dhat). Like the
  // self-repulsion's lambda (§2) an energy per area; its force at a gap g is kappa dhat times a
  // function of g/dhat that grows without bound as g -> 0.
  double stiffness = 10.0;
  // dhat / h: the barrier acts on gaps below dhat = range_fraction * h (h the grid's cell).
  double range_fraction = 0.5;
  // [m]: the gap is g = d - thickness, d the distance to the obstacle; vertices stay at least
  // this far from every obstacle surface.
  double thickness = 1e-3;
  // eps_v [m/s]: below this tangential speed friction is static-like (IPC's mollifier f0 on
  // |u| < eps_v dt, Li et al. 2020 §5); above it the full Coulomb force mu lambda. A sticking cloth
  // creeps at about eps_v tan(theta)/(2 mu) on a slope theta; a smaller eps_v creeps less but
  // makes the mollifier's curvature 2 mu lambda/(eps_v dt) stiffer for Newton (docs/design.md §14).
  double friction_velocity = 1e-2;
  // The share of the safe fraction s an iterate is pulled back to: a_from + factor s (a_to - a_from)
  // (solve_step, optimizer/inner_optimizer.cpp). Below 1, so that the gap stays positive.
  double pullback = 0.9;

  // Throws Error("contact.<field>", ...) naming the bad field.
  void validate() const;
};

}  // namespace fnopt
