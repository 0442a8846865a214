#include <fnopt/adjoint/step_linearization.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/lumped_mass.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/contact/self_contact_term.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// A pivot of the LDL^T factorisation at most this fraction of the largest counts as zero: the
// step's H_FF is then singular to working precision and its solve meaningless.
constexpr double kSingularPivot = 1e-13;

// The stretch, shear and bend terms at unit stiffness, in that order (no repulsion).
std::vector<std::unique_ptr<EnergyTerm>> unit_stiffness_terms(const Grid& grid) {
  Material unit;
  unit.stretch = unit.shear = unit.bend = 1.0;
  unit.repulsion = false;
  return make_cloth_terms(grid, unit);
}

}  // namespace

const char* to_string(StepStationarity stationarity) {
  switch (stationarity) {
    case StepStationarity::Minimum:
      return "minimum";
    case StepStationarity::Saddle:
      return "saddle";
    case StepStationarity::Singular:
      return "singular";
  }
  return "unknown";
}

StepLinearization::StepLinearization(const ResolvedScene& scene)
    : material_(scene.scene.material),
      objective_(scene.grid, scene.scene.material, scene.scene.dt, scene.scene.gravity, scene.scene.obstacles,
                 scene.scene.contact, self_contact_of(scene.scene)),
      unit_terms_(unit_stiffness_terms(scene.grid)),
      scene_handles_(scene.handles.vertices),
      handle_vertices_(scene_handles_),
      handle_vertex_(scene.grid.vertex_count(), 0),
      all_free_(scene.grid.vertex_count()),
      masses_(objective_.masses()),
      areas_(lumped_masses(scene.grid, 1.0)) {
  for (int k = 0; k < scene.grid.vertex_count(); ++k) all_free_[k] = k;
  for (int k : handle_vertices_) handle_vertex_[k] = 1;
}

void StepLinearization::set_released(bool released) {
  // Called before every step's linearisation: the handle set changes at most once per rollout.
  if (released == released_) return;
  released_ = released;
  handle_vertices_ = released ? std::vector<int>{} : scene_handles_;
  for (int k : scene_handles_) handle_vertex_[k] = released ? 0 : 1;
}

StepStationarity StepLinearization::linearize(const VecX& x, const VecX& v, const VecX& a, double time) {
  objective_.begin_step(x, v, time);
  x_start_ = x;
  a_ = a;
  objective_.trial_positions(a, x_);
  hessian_ = &objective_.hessian(a, all_free_, false);
  const long pattern = objective_.hessian_pattern_id();
  if (pattern != masked_pattern_) {
    masked_ = *hessian_;
    masked_pattern_ = pattern;
  } else {
    std::copy_n(hessian_->valuePtr(), hessian_->nonZeros(), masked_.valuePtr());
  }
  for (int column = 0; column < masked_.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator it(masked_, column); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (!handle_vertex_[row / 3] && !handle_vertex_[column / 3]) continue;
      it.valueRef() = row == column ? objective_.inertia_weight(row / 3) : 0.0;
    }

  ++factorizations_;
  use_ldlt_ = false;
  negative_eigenvalues_ = 0;
  if (cholesky_.factorize_matrix(masked_, pattern)) return StepStationarity::Minimum;

  ++factorizations_;
  use_ldlt_ = true;
  if (ldlt_pattern_ != pattern) {
    ldlt_.analyzePattern(masked_);
    ldlt_pattern_ = pattern;
  }
  ldlt_.factorize(masked_);
  negative_eigenvalues_ = -1;
  if (ldlt_.info() != Eigen::Success) return StepStationarity::Singular;
  const VecX pivots = ldlt_.vectorD();
  const double largest = pivots.cwiseAbs().maxCoeff();
  if (!pivots.allFinite() || (pivots.cwiseAbs().array() <= kSingularPivot * largest).any())
    return StepStationarity::Singular;
  negative_eigenvalues_ = static_cast<int>((pivots.array() < 0.0).count());
  return StepStationarity::Saddle;
}

void StepLinearization::solve(const VecX& rhs, VecX& lambda) {
  lambda = rhs;
  for (int k : handle_vertices_) lambda.segment<3>(3 * k).setZero();
  if (use_ldlt_)
    lambda = ldlt_.solve(lambda);
  else
    cholesky_.solve_in_place(lambda.data(), static_cast<int>(lambda.size()), 1);
  for (int k : handle_vertices_) lambda.segment<3>(3 * k).setZero();
  ++solves_;
}

void StepLinearization::stiffness_product(const VecX& lambda, VecX& product) const {
  product.noalias() = *hessian_ * lambda;
  for (Eigen::Index k = 0; k < masses_.size(); ++k)
    product.segment<3>(3 * k) -= objective_.inertia_weight(static_cast<int>(k)) * lambda.segment<3>(3 * k);
}

void StepLinearization::subtract_friction_start_product(const VecX& lambda, VecX& xbar) {
  const ContactTerm* contact = objective_.contact();
  const MeshContactTerm* meshes = objective_.mesh_contact();
  const SelfContactTerm* self = objective_.self_contact();
  const bool analytic = contact && !contact->friction_pairs().empty();
  const bool mesh = meshes && meshes->friction_pair_count() > 0;
  const bool layers = self && self->friction_pair_count() > 0;
  if (!analytic && !mesh && !layers) return;
  friction_buffer_.setZero(x_.size());
  if (analytic) contact->add_friction_start_product(x_, lambda, friction_buffer_);
  if (mesh) meshes->add_friction_start_product(x_, lambda, friction_buffer_);
  if (layers) self->add_friction_start_product(x_, lambda, friction_buffer_);
  xbar -= objective_.dt() * objective_.dt() * friction_buffer_;
}

MaterialGradient StepLinearization::material_gradient(const VecX& lambda) {
  const double dt = objective_.dt();
  const double dt2 = dt * dt;
  MaterialGradient gradient;
  double* stiffness[] = {&gradient.stretch, &gradient.shear, &gradient.bend};
  for (std::size_t t = 0; t < unit_terms_.size(); ++t) {
    gradient_buffer_.setZero(x_.size());
    unit_terms_[t]->accumulate_gradient(x_, gradient_buffer_);
    *stiffness[t] = -dt2 * lambda.dot(gradient_buffer_);
  }
  const Vec3& gravity = objective_.gravity();
  for (Eigen::Index k = 0; k < masses_.size(); ++k) {
    const auto lambda_k = lambda.segment<3>(3 * k);
    const Vec3 moved = x_.segment<3>(3 * k) - x_start_.segment<3>(3 * k);
    gradient.density -=
        dt2 * areas_[k] * lambda_k.dot(a_.segment<3>(3 * k) - gravity + (material_.damping / dt) * moved);
    gradient.damping -= dt * masses_[k] * lambda_k.dot(moved);
    gradient.gravity += dt2 * masses_[k] * lambda_k;
  }
  return gradient;
}

void StepLinearization::advance_tangent(VecX& dx, VecX& dv, const VecX* source) {
  const double dt = objective_.dt();
  tangent_z_ = dx + dt * dv;
  for (int k : handle_vertices_) tangent_z_.segment<3>(3 * k).setZero();
  stiffness_product(tangent_z_, tangent_rhs_);  // dt^4 K z
  tangent_rhs_ /= -(dt * dt);
  for (Eigen::Index k = 0; k < dx.size() / 3; ++k)
    tangent_rhs_.segment<3>(3 * k) -= damping_weight(static_cast<int>(k)) * dv.segment<3>(3 * k);
  if (source) tangent_rhs_ -= *source;
  solve(tangent_rhs_, tangent_a_);
  for (int k : handle_vertices_)
    tangent_a_.segment<3>(3 * k) = -(dx.segment<3>(3 * k) + dt * dv.segment<3>(3 * k)) / (dt * dt);
  dx += dt * dv + dt * dt * tangent_a_;
  dv += dt * tangent_a_;
}

void StepLinearization::log_material_derivative(AdjointParameter coefficient, VecX& out) {
  const double dt = objective_.dt();
  const double dt2 = dt * dt;
  out.setZero(x_.size());
  switch (coefficient) {
    case AdjointParameter::Stretch:
    case AdjointParameter::Shear:
    case AdjointParameter::Bend: {
      // Each term is linear in its stiffness: k dg/dk = dt^2 grad P_k(x) = dt^2 k grad P_k^unit(x).
      const int t = coefficient == AdjointParameter::Stretch ? 0 : coefficient == AdjointParameter::Shear ? 1 : 2;
      unit_terms_[t]->accumulate_gradient(x_, out);
      out *= dt2 * material_coefficient(material_, coefficient);
      return;
    }
    case AdjointParameter::Density:
    case AdjointParameter::Damping:
      break;
    default:
      throw Error("parameter", std::string(to_string(coefficient)) + " is not a material coefficient");
  }
  const Vec3& gravity = objective_.gravity();
  for (Eigen::Index k = 0; k < masses_.size(); ++k) {
    const Vec3 moved = x_.segment<3>(3 * k) - x_start_.segment<3>(3 * k);
    out.segment<3>(3 * k) =
        coefficient == AdjointParameter::Density
            ? Vec3(dt2 * masses_[k] * (a_.segment<3>(3 * k) - gravity + (material_.damping / dt) * moved))
            : Vec3(dt * material_.damping * masses_[k] * moved);
  }
}

void StepLinearization::third_derivative(const VecX& t, double probe, VecX& out) {
  const double norm = t.norm();
  out.setZero(t.size());
  if (norm == 0.0) return;
  const double dt2 = objective_.dt() * objective_.dt();
  const double h = probe;
  objective_.value_gradient(a_, probe_gradient_);
  out -= 2.0 * probe_gradient_;
  for (double sign : {1.0, -1.0}) {
    probe_a_ = a_ + (sign * h / (norm * dt2)) * t;
    objective_.value_gradient(probe_a_, probe_gradient_);
    out += probe_gradient_;
  }
  out *= norm * norm / (h * h);
}

}  // namespace fnopt
