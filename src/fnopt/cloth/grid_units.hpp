#pragma once
// Dimensionless stiffnesses of a scene in grid units: length h, time dt, mass rho h^2
// (docs/design.md §2). They say how stiff one time step is for an optimizer:
//   k~_s = k_s dt^2/(rho h^2),  k~_sh = k_sh dt^2/(rho h^2),  k~_b = k_b dt^2/(rho h^4),
//   g~ = |g| dt^2/h.
// For a fixed cloth, k~_s grows like n^2 and k~_b like n^4 with the resolution n.
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/material.hpp>

namespace fnopt {

struct GridUnitStiffness {
  double stretch = 0.0;
  double shear = 0.0;
  double bend = 0.0;
  double gravity = 0.0;
};

// Acceleration [m/s^2] per grid unit of acceleration: a grid-unit update of 1 moves a vertex by
// one cell width h in one step (x changes by dt^2 a), so a = (h/dt^2) * (grid-unit value).
inline double acceleration_per_grid_unit(const Grid& grid, double dt) { return grid.spacing / (dt * dt); }

inline GridUnitStiffness grid_unit_stiffness(const Grid& grid, const Material& m, double dt, double gravity) {
  const double h2 = grid.spacing * grid.spacing, dt2 = dt * dt;
  return {m.stretch * dt2 / (m.density * h2), m.shear * dt2 / (m.density * h2), m.bend * dt2 / (m.density * h2 * h2),
          gravity * dt2 / grid.spacing};
}

}  // namespace fnopt
