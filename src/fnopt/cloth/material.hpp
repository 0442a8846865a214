#pragma once
// Cloth material in physical units (docs/design.md §2). The energy per stencil:
//   stretch, per edge:        (stretch/2) * h^2 * (|e|/h - 1)^2        stretch [N/m]
//   shear, per quad corner:   (shear/2) * (h^2/4) * (theta - pi/2)^2   shear   [N/m]
//   bend, per hinge:          (bend/2) * beta^2                        bend    [N m]
//   mass, lumped:             density * vertex area                    density [kg/m^2]
//   damping (optional):       implicit force -damping * m * v          damping [1/s]
//   self-repulsion (optional): per non-adjacent vertex pair closer than delta = range * h,
//       -repulsion_stiffness (d - delta)^2 log(d/delta)                   [N/m]
//     built only when `repulsion` is true; a scene decides that (Scene::repulsion, auto/on/off)
#include <string>

namespace fnopt {

struct Material {
  // Defaults: fitted to ARCSim's gray-interlock runs (../shared/data/arcsim, N = 32, xy_v2 and
  // rot_h0, first 3.5 s) by `fnopt fit-material`, the Newton rollout's e_CD against them
  // minimised (docs/design.md §7). Density and bending are ARCSim's own (0.187 kg/m^2,
  // small-curvature 2e-5 N m). The damping stands
  // for the numerical damping of ARCSim's one linearised solve per step, which an exact
  // backward-Euler step does not have: without it fnopt's cloth swings twice as far.
  double stretch = 473.2;
  double shear = 29.18;
  double bend = 2.0e-5;
  double density = 0.187;
  double damping = 4.0;
  // Self-repulsion (cloth/repulsion_term.hpp). A fixed lambda in N/m is the same surface
  // pressure at every resolution; in grid units lambda dt^2/(rho h^2) = 14 at 32^2 (1/30 of the
  // stretch). 10 N/m keeps the folding presets' pairs well apart at little cost in Newton
  // iterations, where a weaker lambda slows Newton and a stronger one costs more iterations
  // (docs/design.md §7).
  bool repulsion = false;
  double repulsion_stiffness = 10.0;  // lambda [N/m]
  double repulsion_range = 1.0;       // delta / h

  // Throws Error naming the field ("material.stretch: ...") for a negative, zero (where a
  // zero is meaningless) or non-finite value.
  void validate() const;
};

// Named presets: "default" (the struct's defaults) and any preset the project ships; also a
// path to a material file written by `fnopt fit-material`. Throws Error for an unknown name.
Material material_preset(const std::string& name);

}  // namespace fnopt
