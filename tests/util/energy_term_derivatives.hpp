#pragma once
// An energy term's gradient and Hessian at x against central differences along one direction: the
// gradient's directional derivative against the energy's, and the Hessian's product against the
// gradient's, each relative. The gradient at x comes first (a contact term covers its state there).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <fnopt/cloth/energy_term.hpp>
#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt::testing {

// The term's Hessian at x, projected or not, assembled over every vertex.
inline Eigen::SparseMatrix<double> assembled_hessian(const EnergyTerm& term, const VecX& x, bool project) {
  std::vector<int> free_index(x.size() / 3);
  for (std::size_t v = 0; v < free_index.size(); ++v) free_index[v] = static_cast<int>(v);
  HessianAssembly assembly(free_index);
  const int handle = term.register_hessian(assembly);
  assembly.finalize();
  assembly.set_zero();
  term.accumulate_hessian(x, project, assembly, handle);
  return assembly.matrix();
}

inline void expect_derivatives_match_differences(const EnergyTerm& term, const VecX& x, const VecX& direction,
                                                 double step = 1e-8, double gradient_tolerance = 1e-5,
                                                 double hessian_tolerance = 1e-4) {
  VecX gradient = VecX::Zero(x.size());
  term.accumulate_gradient(x, gradient);
  const double difference = (term.energy(x + step * direction) - term.energy(x - step * direction)) / (2 * step);
  EXPECT_NEAR(gradient.dot(direction), difference, gradient_tolerance * std::abs(difference));

  VecX plus = VecX::Zero(x.size()), minus = VecX::Zero(x.size());
  term.accumulate_gradient(x + step * direction, plus);
  term.accumulate_gradient(x - step * direction, minus);
  const VecX hessian_product = assembled_hessian(term, x, false) * direction;
  const VecX difference_product = (plus - minus) / (2 * step);
  EXPECT_LT((hessian_product - difference_product).norm(), hessian_tolerance * difference_product.norm());
}

}  // namespace fnopt::testing
