#pragma once
// What an inner optimizer sees of one time step: the backward-Euler objective with the handle
// vertices eliminated. Gradients are masked (zero on fixed dofs), so any update built from them
// leaves the prescribed handle accelerations untouched.
#include <optional>

#include "boundary/dirichlet.hpp"
#include "cloth/backward_euler.hpp"
#include "cloth/material.hpp"

namespace fnopt {

// The scene's material and gravity, which the objective consumes but does not keep: what an
// optimizer needs to build the same step on another grid (optimizer/interpolated_optimizer.hpp).
struct StepPhysics {
  Material material;
  Vec3 gravity = Vec3::Zero();
};

class StepProblem {
 public:
  StepProblem(BackwardEulerObjective& objective, const DirichletSet& dirichlet)
      : objective_(&objective), dirichlet_(&dirichlet) {}

  BackwardEulerObjective& objective() const { return *objective_; }
  const DirichletSet& dirichlet() const { return *dirichlet_; }
  const Grid& grid() const { return objective_->grid(); }

  // The material and gravity the objective was built with, where its owner said so
  // (run_rollout does); nullptr otherwise.
  void set_physics(const Material& material, const Vec3& gravity) { physics_ = StepPhysics{material, gravity}; }
  const StepPhysics* physics() const { return physics_ ? &*physics_ : nullptr; }

  double value(const VecX& a) {
    ++evaluations_;
    return objective_->value(a);
  }
  // Masked gradient at a; returns L(a).
  double value_gradient(const VecX& a, VecX& gradient) {
    ++evaluations_;
    const double value = objective_->value_gradient(a, gradient);
    dirichlet_->zero_fixed(gradient);
    return value;
  }
  // Objective evaluations since construction (a cost measure independent of wall time).
  long evaluations() const { return evaluations_; }

 private:
  BackwardEulerObjective* objective_;
  const DirichletSet* dirichlet_;
  std::optional<StepPhysics> physics_;
  long evaluations_ = 0;
};

}  // namespace fnopt
