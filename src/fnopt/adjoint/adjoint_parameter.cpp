#include <fnopt/adjoint/adjoint_parameter.hpp>

#include <fnopt/util/error.hpp>

namespace fnopt {

const char* to_string(AdjointParameter parameter) {
  switch (parameter) {
    case AdjointParameter::Stretch:
      return "stretch";
    case AdjointParameter::Shear:
      return "shear";
    case AdjointParameter::Bend:
      return "bend";
    case AdjointParameter::Density:
      return "density";
    case AdjointParameter::Damping:
      return "damping";
    case AdjointParameter::Gravity:
      return "gravity";
    case AdjointParameter::HandlePositions:
      return "handle-positions";
    case AdjointParameter::HandlePath:
      return "handle-path";
    case AdjointParameter::InitialPositions:
      return "initial-positions";
    case AdjointParameter::InitialVelocities:
      return "initial-velocities";
  }
  return "unknown";
}

std::vector<AdjointParameter> all_adjoint_parameters() {
  return {AdjointParameter::Stretch,         AdjointParameter::Shear,           AdjointParameter::Bend,
          AdjointParameter::Density,         AdjointParameter::Damping,         AdjointParameter::Gravity,
          AdjointParameter::HandlePositions, AdjointParameter::HandlePath,      AdjointParameter::InitialPositions,
          AdjointParameter::InitialVelocities};
}

AdjointParameter adjoint_parameter_from_name(const std::string& name) {
  std::string known;
  for (AdjointParameter parameter : all_adjoint_parameters()) {
    if (name == to_string(parameter)) return parameter;
    known += (known.empty() ? "" : ", ") + std::string(to_string(parameter));
  }
  throw Error("parameter", "unknown '" + name + "' (known: " + known + ")");
}

bool is_material_coefficient(AdjointParameter parameter) {
  return parameter == AdjointParameter::Stretch || parameter == AdjointParameter::Shear ||
         parameter == AdjointParameter::Bend || parameter == AdjointParameter::Density ||
         parameter == AdjointParameter::Damping;
}

}  // namespace fnopt
