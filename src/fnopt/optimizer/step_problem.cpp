#include <fnopt/optimizer/step_problem.hpp>

#include <limits>

#include <algorithm>

#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/contact/self_contact_term.hpp>

namespace fnopt {

double StepProblem::feasible_fraction(const VecX& a_from, const VecX& a_to) {
  double fraction = obstacle_fraction(a_from, a_to);
  const SelfContactTerm* self = objective_->self_contact();
  const MeshContactTerm* meshes = objective_->mesh_contact();
  if (self || meshes) {
    objective_->trial_positions(a_from, x_from_);
    objective_->trial_positions(a_to, x_to_);
  }
  if (meshes) fraction = std::min(fraction, meshes->safe_fraction(x_from_, x_to_));
  if (self) fraction = std::min(fraction, self->safe_fraction(x_from_, x_to_));
  return fraction;
}

double StepProblem::obstacle_fraction(const VecX& a_from, const VecX& a_to) {
  const ContactTerm* contact = objective_->contact();
  if (!contact) return 1.0;
  // The box of both ends straight from the accelerations, x = x^ + dt^2 a, in one pass that stores
  // nothing: where no obstacle can reach it (far obstacles, docs/design.md §14) that is all it costs.
  const VecX& inertial = objective_->inertial_positions();
  const double dt2 = objective_->dt() * objective_->dt();
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity()), upper = -lower;
  for (Eigen::Index i = 0; i < inertial.size(); i += 3) {
    const Vec3 base = inertial.segment<3>(i);
    const Vec3 from = base + dt2 * a_from.segment<3>(i), to = base + dt2 * a_to.segment<3>(i);
    lower = lower.cwiseMin(from).cwiseMin(to);
    upper = upper.cwiseMax(from).cwiseMax(to);
  }
  if (!contact->may_touch(lower, upper)) return 1.0;
  objective_->trial_positions(a_from, x_from_);
  objective_->trial_positions(a_to, x_to_);
  return contact->safe_fraction(x_from_, x_to_, lower, upper);
}

double StepProblem::feasible_step(const VecX& a, const VecX& direction, double step) {
  if (!has_contact()) return step;
  scratch_ = a + step * direction;
  const double fraction = feasible_fraction(a, scratch_);
  return fraction < 1.0 ? pullback() * fraction * step : step;
}

double StepProblem::pullback() const {
  if (const ContactTerm* contact = objective_->contact()) return contact->params().pullback;
  if (const MeshContactTerm* meshes = objective_->mesh_contact()) return meshes->params().pullback;
  return ContactParams{}.pullback;
}

void StepProblem::carry_blocking_cloth(const SelfContactTerm& self, const VecX& x_start) {
  // A vertex an obstacle carries may be carried into the cloth beside it (a corner pushed into a
  // crease). The pairs that stop the carried move (self-contact's CCD from x_t) are carried along,
  // every vertex of one by the displacement of its most carried one, which keeps the pair as it was
  // at x_t; round after round until the move is free, for at most kCarryRounds. A pair so carried
  // moves as the obstacle does where it touches, so it keeps its distance to it.
  std::vector<SelfContactTerm::Pair> blocking;
  for (int round = 0; round < kCarryRounds && self.safe_fraction(x_start, x_to_, &blocking) < 1.0; ++round) {
    bool carried = false;
    for (const SelfContactTerm::Pair& pair : blocking) {
      Vec3 shift = Vec3::Zero();
      for (const int v : pair.vertices) {
        const Vec3 moved = x_to_.segment<3>(3 * v) - x_start.segment<3>(3 * v);
        if (moved.squaredNorm() > shift.squaredNorm()) shift = moved;
      }
      for (const int v : pair.vertices)
        if (x_to_.segment<3>(3 * v) != x_start.segment<3>(3 * v) + shift) {
          x_to_.segment<3>(3 * v) = x_start.segment<3>(3 * v) + shift;
          carried = true;
        }
    }
    if (!carried) return;  // pairs that the carry cannot free: the step's filter stops them
  }
}

void StepProblem::make_start_feasible(VecX& a) {
  if (!has_contact()) return;
  const double dt2 = objective_->dt() * objective_->dt();
  const VecX& x_start = objective_->start_positions();
  if (const ContactTerm* contact = objective_->contact())
    contact->safe_start_positions(x_start, x_to_);
  else
    x_to_ = x_start;
  if (const MeshContactTerm* meshes = objective_->mesh_contact()) {
    x_from_ = x_to_;
    meshes->safe_start_positions(x_from_, x_to_);
  }
  if (const SelfContactTerm* self = objective_->self_contact(); self && x_to_ != x_start)
    carry_blocking_cloth(*self, x_start);
  scratch_ = a;  // the handles keep their prescribed accelerations
  for (int v = 0; v < dirichlet_->vertex_count(); ++v)
    if (dirichlet_->free_index()[v] >= 0)
      scratch_.segment<3>(3 * v) = (x_to_.segment<3>(3 * v) - x_start.segment<3>(3 * v) -
                                    objective_->dt() * objective_->start_velocities().segment<3>(3 * v)) /
                                   dt2;
  const double fraction = feasible_fraction(scratch_, a);
  if (fraction < 1.0) a = scratch_ + pullback() * fraction * (a - scratch_);
}

}  // namespace fnopt
