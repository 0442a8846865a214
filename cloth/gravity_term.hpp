#pragma once
// Gravity: E = -sum_i m_i g . x_i. Linear in x: constant gradient, no Hessian.
#include "cloth/energy_term.hpp"

namespace fnopt {

class GravityTerm final : public EnergyTerm {
 public:
  GravityTerm(const VecX& masses, const Vec3& gravity);

  const std::string& name() const override { return name_; }
  double energy(const VecX& x) const override { return gradient_.dot(x); }
  double accumulate_gradient(const VecX& x, VecX& grad) const override {
    grad += gradient_;
    return gradient_.dot(x);
  }
  int register_hessian(HessianAssembly&) const override { return -1; }
  void accumulate_hessian(const VecX&, bool, HessianAssembly&, int) const override {}

 private:
  std::string name_ = "gravity";
  VecX gradient_;  // -m_i g, stacked
};

}  // namespace fnopt
