#pragma once
// A box l <= x <= u for the fits' minimisers (bounded_lbfgs.hpp, bounded_gauss_newton.hpp): the
// projection onto it and the variables a step must hold at their bound.
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

inline VecX project_to_box(const VecX& x, const VecX& lower, const VecX& upper) {
  return x.cwiseMax(lower).cwiseMin(upper);
}

// Variables held at a bound: at it, with the gradient pushing out of the box.
inline std::vector<char> held_at_bounds(const VecX& x, const VecX& g, const VecX& lower, const VecX& upper) {
  std::vector<char> held(x.size(), 0);
  for (Eigen::Index i = 0; i < x.size(); ++i) held[i] = (x[i] <= lower[i] && g[i] > 0.0) || (x[i] >= upper[i] && g[i] < 0.0);
  return held;
}

// Throws Error("bounds", ...) for bounds of another size than x0's or with l > u somewhere.
void check_box(const VecX& x0, const VecX& lower, const VecX& upper);

}  // namespace fnopt
