#include <fnopt/fits/box_bounds.hpp>

#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt {

void check_box(const VecX& x0, const VecX& lower, const VecX& upper) {
  require(lower.size() == x0.size() && upper.size() == x0.size(), "bounds",
          "expected " + std::to_string(x0.size()) + " lower and upper bounds");
  require((lower.array() <= upper.array()).all(), "bounds", "a lower bound is above its upper bound");
}

}  // namespace fnopt
