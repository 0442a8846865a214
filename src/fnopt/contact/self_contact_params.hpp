#pragma once
// The settings of self-contact (self_contact_term.hpp, docs/design.md §14).
#include <fnopt/cloth/grid.hpp>

namespace fnopt {

struct SelfContactParams {
  double stiffness = 10.0;  // kappa [N/m], as the obstacles' (contact_params.hpp)
  double range = 1.5e-3;    // dhat [m]: the barrier acts on gaps below it
  double thickness = 1e-3;  // [m]: primitives stay at least this far apart
  // mu between layers: IPC's lagged friction on the pairs within range at the step's start (0: none,
  // as an obstacle's friction defaults to), the obstacles' mollifier (contact_params.hpp) on
  // eps = friction_velocity dt.
  double friction = 0.0;
  double friction_velocity = 1e-2;  // eps_v [m/s], as the obstacles'

  // Throws Error("self-contact-stiffness" / "-range" / "-thickness" / "-friction", ...) naming the bad
  // field.
  void validate() const;
  // Also refuses thickness + range >= h/2 on a grid of cell h (the closest primitives of a flat
  // cloth that share no vertex are h/sqrt(2) apart: the barrier must not act on a flat cloth),
  // naming the range.
  void validate_for(const Grid& grid) const;
};

}  // namespace fnopt
