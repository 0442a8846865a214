#pragma once
// The quantities a rollout's gradient is taken with respect to (docs/design.md §15), by kind,
// with the names the command line and reports use.
#include <string>
#include <vector>

namespace fnopt {

enum class AdjointParameter {
  Stretch,            // material.stretch [N/m]
  Shear,              // material.shear [N/m]
  Bend,               // material.bend [N m]
  Density,            // material.density [kg/m^2]
  Damping,            // material.damping [1/s]
  Gravity,            // the gravity vector [m/s^2]
  HandlePositions,    // every handle's target at every step, one Vec3 each
  HandlePath,         // the control points of handle path offsets (adjoint/handle_path.hpp)
  InitialPositions,   // x_0, every vertex
  InitialVelocities,  // v_0, every vertex
};

// "stretch", "shear", "bend", "density", "damping", "gravity", "handle-positions", "handle-path",
// "initial-positions", "initial-velocities".
const char* to_string(AdjointParameter parameter);
// The inverse of to_string; throws Error("parameter", "unknown ...") listing the names.
AdjointParameter adjoint_parameter_from_name(const std::string& name);
// Every kind, in the enum's order.
std::vector<AdjointParameter> all_adjoint_parameters();
// The five positive material coefficients, whose gradients are also given in log coordinates.
bool is_material_coefficient(AdjointParameter parameter);

}  // namespace fnopt
