#pragma once
// Cloth material in physical units (DESIGN.md §2). The energy per stencil:
//   stretch, per edge:        (stretch/2) * h^2 * (|e|/h - 1)^2        stretch [N/m]
//   shear, per quad corner:   (shear/2) * (h^2/4) * (theta - pi/2)^2   shear   [N/m]
//   bend, per hinge:          (bend/2) * beta^2                        bend    [N m]
//   mass, lumped:             density * vertex area                    density [kg/m^2]
//   damping (optional):       implicit force -damping * m * v          damping [1/s]
#include <string>

namespace fnopt {

struct Material {
  // Defaults: ARCSim's gray-interlock (../shared/data/arcsim): its density and small-curvature
  // bending; its stretch is nonlinear (16-37 N/m at small strain, 4-10x stiffer above ~17 %),
  // so the linear stretch is the one that keeps the benchmark scene's peak strain at ~17 %
  // (Newton sweep at 32^2: 100 N/m gives 47 %, 300 N/m gives 17 %). See README.
  double stretch = 300.0;
  double shear = 3.0;
  double bend = 2.0e-5;
  double density = 0.187;
  double damping = 0.0;

  // Throws Error naming the field ("material.stretch: ...") for a negative, zero (where a
  // zero is meaningless) or non-finite value.
  void validate() const;
};

// Named presets: "default" (the struct's defaults) and any preset the project ships; also a
// path to a material file written by `fnopt fit-material`. Throws Error for an unknown name.
Material material_preset(const std::string& name);

}  // namespace fnopt
