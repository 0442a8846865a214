#include <fnopt/adjoint/material_gradient.hpp>

#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

template <class Coefficients, class Value>
Value& select(Coefficients& c, AdjointParameter parameter) {
  switch (parameter) {
    case AdjointParameter::Stretch:
      return c.stretch;
    case AdjointParameter::Shear:
      return c.shear;
    case AdjointParameter::Bend:
      return c.bend;
    case AdjointParameter::Density:
      return c.density;
    case AdjointParameter::Damping:
      return c.damping;
    default:
      throw Error("parameter", std::string(to_string(parameter)) + " is not a material coefficient");
  }
}

}  // namespace

MaterialGradient& MaterialGradient::operator+=(const MaterialGradient& other) {
  stretch += other.stretch;
  shear += other.shear;
  bend += other.bend;
  density += other.density;
  damping += other.damping;
  gravity += other.gravity;
  return *this;
}

double MaterialGradient::coefficient(AdjointParameter parameter) const {
  return select<const MaterialGradient, const double>(*this, parameter);
}

double& material_coefficient(Material& material, AdjointParameter parameter) {
  return select<Material, double>(material, parameter);
}

double material_coefficient(const Material& material, AdjointParameter parameter) {
  return select<const Material, const double>(material, parameter);
}

}  // namespace fnopt
