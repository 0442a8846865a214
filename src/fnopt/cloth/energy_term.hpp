#pragma once
// One term of the potential energy P(x) of the cloth (docs/design.md §2).
#include <string>

#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;

  virtual const std::string& name() const = 0;
  virtual double energy(const VecX& x) const = 0;
  // Adds grad E(x) to `grad` and returns E(x).
  virtual double accumulate_gradient(const VecX& x, VecX& grad) const = 0;
  // Registers the term's stencils with the Hessian pattern; returns the handle that
  // accumulate_hessian takes (-1 when the term has no Hessian).
  virtual int register_hessian(HessianAssembly& assembly) const = 0;
  // Adds hess E(x) into the assembly's target, each stencil's matrix projected to PSD if `project`.
  virtual void accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const = 0;
  // With the assembly's target ExactAndProjected: hess E(x) to its lower blocks and the projected one
  // to its matrix. Here by evaluating each stencil twice; a term that can evaluates each once.
  virtual void accumulate_hessian_pair(const VecX& x, HessianAssembly& assembly, int handle) const {
    assembly.select(HessianAssembly::Target::LowerBlocks);
    accumulate_hessian(x, false, assembly, handle);
    assembly.select(HessianAssembly::Target::Matrix);
    accumulate_hessian(x, true, assembly, handle);
    assembly.select(HessianAssembly::Target::ExactAndProjected);
  }
};

}  // namespace fnopt
