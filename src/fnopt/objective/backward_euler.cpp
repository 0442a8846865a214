#include <fnopt/objective/backward_euler.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/lumped_mass.hpp>
#include <fnopt/cloth/repulsion_term.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

BackwardEulerObjective::BackwardEulerObjective(const Grid& grid, const Material& material, double dt,
                                               const Vec3& gravity)
    : grid_(grid),
      material_(material),
      dt_(dt),
      damping_(material.damping),
      gravity_(gravity),
      masses_(lumped_masses(grid, material.density)),
      terms_(make_cloth_terms(grid, material)),
      x_trial_(grid.dof_count()),
      grad_x_(grid.dof_count()) {
  require(std::isfinite(dt) && dt > 0.0, "dt", "must be a positive time step in seconds");
  material.validate();
  for (const auto& term : terms_)
    if (auto* r = dynamic_cast<RepulsionTerm*>(term.get())) repulsion_ = r;
  begin_step(grid.rest_positions(), VecX::Zero(grid.dof_count()));
}

BackwardEulerObjective::BackwardEulerObjective(const Grid& grid, const Material& material, double dt,
                                               const Vec3& gravity, std::vector<Obstacle> obstacles,
                                               const ContactParams& contact,
                                               const std::optional<SelfContactParams>& self_contact)
    : BackwardEulerObjective(grid, material, dt, gravity) {
  std::vector<Obstacle> analytic, meshes;
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    (obstacles[k].is_mesh() ? mesh_index_ : analytic_index_).push_back(static_cast<int>(k));
    (obstacles[k].is_mesh() ? meshes : analytic).push_back(std::move(obstacles[k]));
  }
  if (!analytic.empty()) {
    auto term = std::make_unique<ContactTerm>(grid, std::move(analytic), contact);
    contact_ = term.get();
    terms_.push_back(std::move(term));
  }
  if (!meshes.empty()) {
    auto term = std::make_unique<MeshContactTerm>(grid, std::move(meshes), contact);
    mesh_contact_ = term.get();
    terms_.push_back(std::move(term));
  }
  if (self_contact) {
    auto term = std::make_unique<SelfContactTerm>(grid, *self_contact);
    self_contact_ = term.get();
    terms_.push_back(std::move(term));
  }
  if (contact_ || mesh_contact_ || self_contact_) begin_step(x_start_, v_start_);
}

void BackwardEulerObjective::begin_step(const VecX& x, const VecX& v, double time,
                                        const ObstacleOffsets* obstacle_offsets) {
  x_start_ = x;
  v_start_ = v;
  x_inertial_ = x + dt_ * v;
  time_ = time;
  if (repulsion_) repulsion_->begin_step(x_start_, x_inertial_);
  // The offsets of each term's obstacles, picked from the scene's list.
  auto picked = [&](const std::vector<int>& index) {
    ObstacleOffsets offsets;
    for (int k : index) {
      offsets.start.push_back(obstacle_offsets->start.at(k));
      offsets.end.push_back(obstacle_offsets->end.at(k));
    }
    return offsets;
  };
  if (obstacle_offsets)
    require(obstacle_offsets->start.size() == analytic_index_.size() + mesh_index_.size() &&
                obstacle_offsets->end.size() == obstacle_offsets->start.size(),
            "obstacles", "expected " + std::to_string(analytic_index_.size() + mesh_index_.size()) +
                             " offsets (one per obstacle)");
  if (contact_) {
    const ObstacleOffsets offsets = obstacle_offsets ? picked(analytic_index_) : ObstacleOffsets{};
    contact_->begin_step(x_start_, time, dt_, obstacle_offsets ? &offsets : nullptr);
  }
  if (mesh_contact_) {
    const ObstacleOffsets offsets = obstacle_offsets ? picked(mesh_index_) : ObstacleOffsets{};
    mesh_contact_->begin_step(x_start_, x_inertial_, time, dt_, obstacle_offsets ? &offsets : nullptr);
  }
  if (self_contact_) self_contact_->begin_step(x_start_, x_inertial_, dt_);
}

double BackwardEulerObjective::value(const VecX& a) const {
  trial_positions(a, x_trial_);
  double total = 0.0;
  for (Eigen::Index k = 0; k < masses_.size(); ++k) {
    const auto ak = a.segment<3>(3 * k);
    total += masses_[k] * dt_ * dt_ * (0.5 * ak.squaredNorm() - gravity_.dot(ak));
    if (damping_ > 0.0)
      total +=
          damping_ * masses_[k] / (2.0 * dt_) * (x_trial_.segment<3>(3 * k) - x_start_.segment<3>(3 * k)).squaredNorm();
  }
  for (const auto& term : terms_) total += term->energy(x_trial_);
  return total;
}

double BackwardEulerObjective::value_gradient(const VecX& a, VecX& grad) const {
  trial_positions(a, x_trial_);
  grad_x_.setZero();
  double total = 0.0;
  for (const auto& term : terms_) total += term->accumulate_gradient(x_trial_, grad_x_);
  const double dt2 = dt_ * dt_;
  grad.resize(a.size());
  for (Eigen::Index k = 0; k < masses_.size(); ++k) {
    const auto ak = a.segment<3>(3 * k);
    total += masses_[k] * dt2 * (0.5 * ak.squaredNorm() - gravity_.dot(ak));
    Vec3 gk = dt2 * (masses_[k] * (ak - gravity_) + grad_x_.segment<3>(3 * k));
    if (damping_ > 0.0) {
      const Vec3 dx = x_trial_.segment<3>(3 * k) - x_start_.segment<3>(3 * k);
      total += damping_ * masses_[k] / (2.0 * dt_) * dx.squaredNorm();
      gk += dt2 * damping_ * masses_[k] / dt_ * dx;
    }
    grad.segment<3>(3 * k) = gk;
  }
  return total;
}

namespace {
std::atomic<long> next_pattern_id{0};  // hessian_pattern_id() of the next pattern built
}  // namespace

const Eigen::SparseMatrix<double>& BackwardEulerObjective::hessian(const VecX& a, const std::vector<int>& free_index,
                                                                   bool project) {
  return assemble_hessian(a, free_index, project, HessianAssembly::Target::Matrix).matrix();
}

const SymmetricBlockMatrix& BackwardEulerObjective::hessian_blocks(const VecX& a, const std::vector<int>& free_index,
                                                                   bool project) {
  return assemble_hessian(a, free_index, project, HessianAssembly::Target::LowerBlocks).lower_blocks();
}

BackwardEulerObjective::HessianPair BackwardEulerObjective::hessian_pair(const VecX& a,
                                                                         const std::vector<int>& free_index) {
  const HessianAssembly& assembly = assemble_hessian(a, free_index, true, HessianAssembly::Target::ExactAndProjected);
  return {assembly.lower_blocks(), assembly.matrix()};
}

const HessianAssembly& BackwardEulerObjective::assemble_hessian(const VecX& a, const std::vector<int>& free_index,
                                                                bool project, HessianAssembly::Target target) {
  trial_positions(a, x_trial_);
  if (self_contact_) self_contact_->cover(x_trial_);  // may change its pattern
  if (mesh_contact_) mesh_contact_->cover(x_trial_);
  const std::pair<long, long> generation = {repulsion_ ? repulsion_->pattern_generation() : 0,
                                            self_contact_ ? self_contact_->pattern_generation() : 0};
  if (!assembly_ || free_index != hessian_free_index_ || generation != assembled_generation_) {
    hessian_free_index_ = free_index;
    assembled_generation_ = generation;
    pattern_id_ = next_pattern_id.fetch_add(1) + 1;
    assembly_ = std::make_unique<HessianAssembly>(free_index);
    term_handles_.clear();
    for (const auto& term : terms_) term_handles_.push_back(term->register_hessian(*assembly_));
    assembly_->finalize();
  }
  assembly_->set_zero(target);
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    if (term_handles_[t] < 0) continue;
    if (target == HessianAssembly::Target::ExactAndProjected)
      terms_[t]->accumulate_hessian_pair(x_trial_, *assembly_, term_handles_[t]);
    else
      terms_[t]->accumulate_hessian(x_trial_, project, *assembly_, term_handles_[t]);
  }
  const double dt2 = dt_ * dt_;
  assembly_->scale(dt2 * dt2);
  for (Eigen::Index k = 0; k < masses_.size(); ++k)
    assembly_->add_vertex_diagonal(static_cast<int>(k), inertia_weight(static_cast<int>(k)));
  return *assembly_;
}

double BackwardEulerObjective::residual_acceleration(const VecX& gradient) const {
  double largest = 0.0;
  for (Eigen::Index k = 0; k < masses_.size(); ++k)
    largest = std::max(largest, gradient.segment<3>(3 * k).cwiseAbs().maxCoeff() / masses_[k]);
  return largest / (dt_ * dt_);
}

double BackwardEulerObjective::potential(const VecX& x) const {
  double total = 0.0;
  for (const auto& term : terms_)
    total += term.get() == static_cast<const EnergyTerm*>(contact_)        ? contact_->barrier_energy(x)
             : term.get() == static_cast<const EnergyTerm*>(mesh_contact_) ? mesh_contact_->barrier_energy(x)
                                                                           : term->energy(x);
  for (Eigen::Index k = 0; k < masses_.size(); ++k) total -= masses_[k] * gravity_.dot(x.segment<3>(3 * k));
  return total;
}

double BackwardEulerObjective::kinetic(const VecX& v) const {
  double total = 0.0;
  for (Eigen::Index k = 0; k < masses_.size(); ++k) total += 0.5 * masses_[k] * v.segment<3>(3 * k).squaredNorm();
  return total;
}

}  // namespace fnopt
