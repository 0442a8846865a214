#include "cloth/gravity_term.hpp"

namespace fnopt {

GravityTerm::GravityTerm(const VecX& masses, const Vec3& gravity) : gradient_(3 * masses.size()) {
  for (Eigen::Index k = 0; k < masses.size(); ++k)
    gradient_.segment<3>(3 * k) = -masses[k] * gravity;
}

}  // namespace fnopt
