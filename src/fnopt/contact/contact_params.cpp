#include <fnopt/contact/contact_params.hpp>

#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

void ContactParams::validate() const {
  require(std::isfinite(stiffness) && stiffness > 0.0, "contact.stiffness", "must be a positive finite number [N/m]");
  require(std::isfinite(range_fraction) && range_fraction > 0.0, "contact.range",
          "must be a positive fraction of the grid cell h");
  require(std::isfinite(thickness) && thickness >= 0.0, "contact.thickness", "must be a finite length >= 0 [m]");
  require(std::isfinite(friction_velocity) && friction_velocity > 0.0, "contact.friction_velocity",
          "must be a positive speed [m/s]");
  require(pullback > 0.0 && pullback < 1.0, "contact.pullback", "must lie in (0, 1)");
}

}  // namespace fnopt
