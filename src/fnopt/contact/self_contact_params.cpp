#include <fnopt/contact/self_contact_params.hpp>

#include <cmath>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

void SelfContactParams::validate() const {
  require(std::isfinite(stiffness) && stiffness > 0.0, "self-contact-stiffness",
          "must be a positive finite number [N/m]");
  require(std::isfinite(range) && range > 0.0, "self-contact-range", "must be a positive length [m]");
  require(std::isfinite(thickness) && thickness >= 0.0, "self-contact-thickness", "must be a finite length >= 0 [m]");
  require(std::isfinite(friction) && friction >= 0.0, "self-contact-friction", "must be a finite number >= 0");
  require(std::isfinite(friction_velocity) && friction_velocity > 0.0, "self-contact-friction-velocity",
          "must be a positive speed [m/s]");
}

void SelfContactParams::validate_for(const Grid& grid) const {
  validate();
  require(thickness + range < 0.5 * grid.spacing, "self-contact-range",
          "thickness + range = " + number_text(thickness + range) + " m must stay below half the grid's cell, " +
              number_text(0.5 * grid.spacing) + " m: the closest primitives of a flat cloth that share no vertex are " +
              number_text(grid.spacing / std::sqrt(2.0)) + " m apart");
}

}  // namespace fnopt
