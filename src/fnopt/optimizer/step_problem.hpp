#pragma once
// What an inner optimizer sees of one time step: the backward-Euler objective with the handle
// vertices eliminated. Gradients are masked (zero on fixed dofs), so any update built from them
// leaves the prescribed handle accelerations untouched.
// With obstacles (docs/design.md §14) it also says how far a move stays outside them
// (feasible_fraction), which solve_step and the line searches use so that no iterate ever enters an
// obstacle; without obstacles those calls cost nothing.
#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>

namespace fnopt {

class SelfContactTerm;

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
    ++gradient_evaluations_;
    const double value = objective_->value_gradient(a, gradient);
    dirichlet_->zero_fixed(gradient);
    return value;
  }
  // Objective evaluations since construction (a cost measure independent of wall time), and those
  // of them with the gradient.
  long evaluations() const { return evaluations_; }
  long gradient_evaluations() const { return gradient_evaluations_; }

  // Whether the objective has obstacles or self-contact.
  bool has_contact() const {
    return objective_->contact() != nullptr || objective_->mesh_contact() != nullptr ||
           objective_->self_contact() != nullptr;
  }
  // The largest s in [0, 1] such that no vertex enters the contact thickness of an obstacle (posed at
  // the step's end, contact/ccd.hpp) and no two cloth primitives come within the self-contact
  // thickness (contact/additive_ccd.hpp) on the straight path from x(a_from) to x(a_to) before s; 1
  // without contact.
  double feasible_fraction(const VecX& a_from, const VecX& a_to);
  // The first trial of a line search from a along `direction`: `step`, or pullback s step where only
  // the fraction s of it is feasible.
  double feasible_step(const VecX& a, const VecX& direction, double step);
  // The share of the safe fraction a pulled-back iterate keeps (ContactParams::pullback).
  double pullback() const;
  // Moves the step's start a_0 to a feasible one: from the safe start a_s (every free vertex at x_t,
  // or carried along by an obstacle that would sweep over it: ContactTerm::safe_start_positions and
  // MeshContactTerm::safe_start_positions; the
  // handles prescribed) toward a_0, a = a_s + pullback s (a_0 - a_s) where only the fraction s of
  // that move is feasible. No change without obstacles or where a_0 is reached safely.
  // A pair of the cloth that the carried start would bring within self-contact's thickness is
  // carried too (carry_blocking_cloth).
  void make_start_feasible(VecX& a);

 private:
  // feasible_fraction's obstacle part (1 without obstacles).
  double obstacle_fraction(const VecX& a_from, const VecX& a_to);
  // Carries, beside the vertices the obstacles carried into x_to_, the pairs of the cloth that the
  // carried move from x_start would bring within self-contact's thickness.
  void carry_blocking_cloth(const SelfContactTerm& self, const VecX& x_start);
  static constexpr int kCarryRounds = 64;
  BackwardEulerObjective* objective_;
  const DirichletSet* dirichlet_;
  long evaluations_ = 0, gradient_evaluations_ = 0;
  VecX x_from_, x_to_, scratch_;
};

}  // namespace fnopt
