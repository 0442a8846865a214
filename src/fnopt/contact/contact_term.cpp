#include <fnopt/contact/contact_term.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <fnopt/contact/ccd.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

ContactTerm::ContactTerm(const Grid& grid, std::vector<Obstacle> obstacles, const ContactParams& params)
    : vertex_count_(grid.vertex_count()),
      obstacles_(std::move(obstacles)),
      params_(validated(params)),
      kernel_{params.stiffness, params.range_fraction * grid.spacing},
      start_offsets_(obstacles_.size(), Vec3::Zero()),
      end_offsets_(obstacles_.size(), Vec3::Zero()),
      lower_(obstacles_.size()),
      upper_(obstacles_.size()),
      vertices_(grid.vertex_count()),
      near_(obstacles_.size(), 1) {
  require(!obstacles_.empty(), "obstacles", "a contact term needs at least one obstacle");
  for (std::size_t k = 0; k < obstacles_.size(); ++k) obstacles_[k].bounds(lower_[k], upper_[k]);
  std::iota(vertices_.begin(), vertices_.end(), 0);
}

void ContactTerm::begin_step(const VecX& x_start, double time, double dt, const ObstacleOffsets* offsets) {
  mollifier_.epsilon = params_.friction_velocity * dt;
  if (offsets) {
    require(offsets->start.size() == obstacles_.size() && offsets->end.size() == obstacles_.size(), "obstacles",
            "expected " + std::to_string(obstacles_.size()) + " offsets (one per obstacle)");
    start_offsets_ = offsets->start;
    end_offsets_ = offsets->end;
  } else {
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      start_offsets_[k] = obstacles_[k].offset(time);
      end_offsets_[k] = obstacles_[k].offset(time + dt);
    }
  }
  friction_pairs_.clear();
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const Obstacle& obstacle = obstacles_[k];
    if (obstacle.friction() == 0.0) continue;
    for (int i = 0; i < vertex_count_; ++i) {
      const Vec3 p = x_start.segment<3>(3 * i);
      const SignedDistance s = obstacle.evaluate(p, start_offsets_[k]);
      const double gap = s.distance - params_.thickness;
      if (!(gap > 0.0 && gap < kernel_.range)) continue;
      FrictionPair pair;
      pair.vertex = i;
      pair.obstacle = static_cast<int>(k);
      pair.weight = obstacle.friction() * -kernel_.barrier_derivative(gap);
      pair.basis = tangent_basis(s.normal);
      pair.start = p;
      pair.obstacle_motion = end_offsets_[k] - start_offsets_[k];
      friction_pairs_.push_back(pair);
    }
  }
}

bool ContactTerm::may_reach(std::size_t k, const Vec3& lower, const Vec3& upper, double reach) const {
  const Obstacle& obstacle = obstacles_[k];
  if (obstacle.shape() == ObstacleShape::Plane) {
    // The box's signed distance from the plane is that of its corner lowest along the unit normal n.
    const Vec3 n = obstacle.axis().normalized();
    const Vec3 centre = 0.5 * (lower + upper), half = 0.5 * (upper - lower);
    return n.dot(centre - obstacle.point() - end_offsets_[k]) - n.cwiseAbs().dot(half) < reach;
  }
  const Vec3 grown_lower = lower_[k] + end_offsets_[k] - Vec3::Constant(reach);
  const Vec3 grown_upper = upper_[k] + end_offsets_[k] + Vec3::Constant(reach);
  return (upper.array() >= grown_lower.array()).all() && (lower.array() <= grown_upper.array()).all();
}

bool ContactTerm::may_touch(const Vec3& lower, const Vec3& upper) const {
  for (std::size_t k = 0; k < obstacles_.size(); ++k)
    if (may_reach(k, lower, upper, params_.thickness)) return true;
  return false;
}

bool ContactTerm::mark_near_obstacles(const VecX& x) const {
  // One pass over the vertices (a rowwise reduction of the 3 x n view would take six strided ones).
  Vec3 cloth_lower = Vec3::Constant(std::numeric_limits<double>::infinity()), cloth_upper = -cloth_lower;
  for (int i = 0; i < vertex_count_; ++i) {
    cloth_lower = cloth_lower.cwiseMin(x.segment<3>(3 * i));
    cloth_upper = cloth_upper.cwiseMax(x.segment<3>(3 * i));
  }
  bool any = false;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    near_[k] = may_reach(k, cloth_lower, cloth_upper, params_.thickness + kernel_.range);
    any = any || near_[k];
  }
  return any;
}

double ContactTerm::vertex_barrier(const Vec3& p, Vec3* gradient, Mat3* hessian, bool project) const {
  double total = 0.0;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    if (!near_[k]) continue;
    const Obstacle& obstacle = obstacles_[k];
    if (!gradient && !hessian) {
      const double gap = obstacle.distance(p, end_offsets_[k]) - params_.thickness;
      if (gap < kernel_.range) total += kernel_.barrier(gap);
      continue;
    }
    const SignedDistance s = obstacle.evaluate(p, end_offsets_[k]);
    const double gap = s.distance - params_.thickness;
    if (gap >= kernel_.range) continue;
    if (!(gap > 0.0)) return std::numeric_limits<double>::infinity();
    total += kernel_.barrier(gap);
    const double slope = kernel_.barrier_derivative(gap);  // < 0
    if (gradient) *gradient += slope * s.normal;
    if (hessian)
      *hessian += kernel_.barrier_second_derivative(gap) * s.normal * s.normal.transpose() +
                  (project ? -slope : slope) * s.hessian;
  }
  return total;
}

double ContactTerm::barrier_energy(const VecX& x) const {
  if (!mark_near_obstacles(x)) return 0.0;
  double total = 0.0;
#pragma omp parallel for reduction(+ : total) schedule(static) if (vertex_count_ >= kParallelThreshold)
  for (int i = 0; i < vertex_count_; ++i) total += vertex_barrier(x.segment<3>(3 * i), nullptr, nullptr, false);
  return total;
}

double ContactTerm::energy(const VecX& x) const {
  double total = barrier_energy(x);
  for (const FrictionPair& pair : friction_pairs_) total += mollifier_.energy(pair, x.segment<3>(3 * pair.vertex));
  return total;
}

double ContactTerm::accumulate_gradient(const VecX& x, VecX& grad) const {
  double total = 0.0;
  if (mark_near_obstacles(x)) {
#pragma omp parallel for reduction(+ : total) schedule(static) if (vertex_count_ >= kParallelThreshold)
    for (int i = 0; i < vertex_count_; ++i) {
      Vec3 g = Vec3::Zero();
      total += vertex_barrier(x.segment<3>(3 * i), &g, nullptr, false);
      grad.segment<3>(3 * i) += g;
    }
  }
  Vec3 g;
  for (const FrictionPair& pair : friction_pairs_) {
    total += mollifier_.gradient(pair, x.segment<3>(3 * pair.vertex), g);
    grad.segment<3>(3 * pair.vertex) += g;
  }
  return total;
}

int ContactTerm::register_hessian(HessianAssembly& assembly) const {
  return assembly.add_stencils(vertices_.data(), vertices_.size(), 1);
}

void ContactTerm::accumulate_hessian(const VecX& x, bool project, HessianAssembly& assembly, int handle) const {
  if (mark_near_obstacles(x)) {
    // Each vertex writes only its own diagonal block: the loop is free of races.
#pragma omp parallel for schedule(static) if (vertex_count_ >= kParallelThreshold)
    for (int i = 0; i < vertex_count_; ++i) {
      Mat3 H = Mat3::Zero();
      vertex_barrier(x.segment<3>(3 * i), nullptr, &H, project);
      if (!H.isZero(0.0)) assembly.scatter<1>(handle, i, H);
    }
  }
  Mat3 H;
  for (const FrictionPair& pair : friction_pairs_) {
    mollifier_.hessian(pair, x.segment<3>(3 * pair.vertex), H);
    assembly.scatter<1>(handle, pair.vertex, H);
  }
}

double ContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to) const {
  // Every vertex's straight path lies in the box of both end states: an obstacle that cannot reach
  // that box within the thickness leaves every path whole, with no vertex tested.
  Vec3 swept_lower = Vec3::Constant(std::numeric_limits<double>::infinity()), swept_upper = -swept_lower;
  for (int i = 0; i < vertex_count_; ++i) {
    swept_lower = swept_lower.cwiseMin(x_from.segment<3>(3 * i)).cwiseMin(x_to.segment<3>(3 * i));
    swept_upper = swept_upper.cwiseMax(x_from.segment<3>(3 * i)).cwiseMax(x_to.segment<3>(3 * i));
  }
  return safe_fraction(x_from, x_to, swept_lower, swept_upper);
}

double ContactTerm::safe_fraction(const VecX& x_from, const VecX& x_to, const Vec3& lower, const Vec3& upper) const {
  double fraction = 1.0;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    if (!may_reach(k, lower, upper, params_.thickness)) continue;
    for (int i = 0; i < vertex_count_; ++i) {
      const Vec3 p0 = x_from.segment<3>(3 * i), p1 = x_to.segment<3>(3 * i);
      if (p0 == p1) continue;  // a vertex that does not move cannot enter an obstacle
      fraction = std::min(
          fraction, fnopt::safe_fraction(obstacles_[k], p0, p1, end_offsets_[k], end_offsets_[k], params_.thickness));
    }
  }
  return fraction;
}

void ContactTerm::add_friction_start_product(const VecX& x, const VecX& lambda, VecX& out) const {
  for (const FrictionPair& pair : friction_pairs_) {
    const Obstacle& obstacle = obstacles_[pair.obstacle];
    const SignedDistance s = obstacle.evaluate(pair.start, start_offsets_[pair.obstacle]);
    const double gap = s.distance - params_.thickness;
    const Vec3& n = s.normal;
    const Vec3 w = x.segment<3>(3 * pair.vertex) - pair.start - pair.obstacle_motion;
    const Vec3 z = w - n * n.dot(w);
    const double y = z.norm();
    const double phi = mollifier_.f1_over_y(y);
    const Mat3 j_psi = phi * Mat3::Identity() + mollifier_.f1_over_y_slope_over_y(y) * z * z.transpose();
    const Mat3 projector = Mat3::Identity() - n * n.transpose();
    const Mat3 normal_turn = -(n.dot(w) * Mat3::Identity() + n * w.transpose()) * s.hessian;
    const Mat3 jacobian = -obstacle.friction() * kernel_.barrier_second_derivative(gap) * phi * z * n.transpose() +
                          pair.weight * j_psi * (normal_turn - projector);
    out.segment<3>(3 * pair.vertex) += jacobian.transpose() * lambda.segment<3>(3 * pair.vertex);
  }
}

void ContactTerm::safe_start_positions(const VecX& x_start, VecX& x_safe) const {
  x_safe = x_start;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const Vec3 motion = end_offsets_[k] - start_offsets_[k];
    if (motion.isZero(0.0)) continue;
    for (int i = 0; i < vertex_count_; ++i) {
      const Vec3 p = x_start.segment<3>(3 * i);
      if (fnopt::safe_fraction(obstacles_[k], p, p, start_offsets_[k], end_offsets_[k], params_.thickness) < 1.0)
        x_safe.segment<3>(3 * i) = p + motion;
    }
  }
}

}  // namespace fnopt
