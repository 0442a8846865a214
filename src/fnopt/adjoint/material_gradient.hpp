#pragma once
// The derivatives of a loss with respect to the material and gravity (docs/design.md §15), and
// the material's coefficients by parameter kind.
#include <fnopt/adjoint/adjoint_parameter.hpp>
#include <fnopt/cloth/material.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

struct MaterialGradient {
  double stretch = 0.0;
  double shear = 0.0;
  double bend = 0.0;
  double density = 0.0;
  double damping = 0.0;
  Vec3 gravity = Vec3::Zero();

  MaterialGradient& operator+=(const MaterialGradient& other);
  // The derivative for a material coefficient (is_material_coefficient); throws
  // Error("parameter", ...) for another kind.
  double coefficient(AdjointParameter parameter) const;
};

// The material's value of a coefficient kind; throws Error("parameter", ...) for another kind.
double& material_coefficient(Material& material, AdjointParameter parameter);
double material_coefficient(const Material& material, AdjointParameter parameter);

}  // namespace fnopt
