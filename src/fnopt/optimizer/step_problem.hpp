#pragma once
// What an inner optimizer sees of one time step: the backward-Euler objective with the handle
// vertices eliminated. Gradients are masked (zero on fixed dofs), so any update built from them
// leaves the prescribed handle accelerations untouched.
#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/cloth/backward_euler.hpp>

namespace fnopt {

class StepProblem {
 public:
  StepProblem(BackwardEulerObjective& objective, const DirichletSet& dirichlet)
      : objective_(&objective), dirichlet_(&dirichlet) {}

  BackwardEulerObjective& objective() const { return *objective_; }
  const DirichletSet& dirichlet() const { return *dirichlet_; }
  const Grid& grid() const { return objective_->grid(); }

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
  long evaluations_ = 0;
};

}  // namespace fnopt
