#include <fnopt/contact/self_contact_kernel.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>

#include <fnopt/cloth/repulsion_kernel.hpp>
#include <fnopt/contact/box.hpp>
#include <fnopt/contact/friction.hpp>

namespace fnopt {
namespace {

// b on the gap g = sqrt(s) - thickness of a squared distance s.
struct GapBarrier {
  RepulsionKernel scalar;  // b(g), b'(g), b''(g) with kappa and dhat
  double thickness;

  double gap(double s) const { return std::sqrt(s) - thickness; }
  // b(g(s)) for 0 < g < dhat, its gradient and Hessian in x from those of s (the header's chain
  // rule: db/ds = b'/(2d), d2b/ds2 = (b'' - b'/d)/(4d^2)).
  double with_derivatives(double s, const Vec12& grad_s, const Mat12* hess_s, Vec12* grad, Mat12* hess) const {
    const double d = std::sqrt(s);
    const double g = d - thickness;
    const double b1 = scalar.barrier_derivative(g);
    const double slope = b1 / (2.0 * d);
    if (grad) *grad = slope * grad_s;
    if (hess) {
      const double curvature = (scalar.barrier_second_derivative(g) - b1 / d) / (4.0 * d * d);
      *hess = curvature * grad_s * grad_s.transpose() + slope * *hess_s;
    }
    return scalar.barrier(g);
  }
};

// Where the gap is not inside (0, dhat): zero derivatives, and the energy (0 beyond the range,
// +inf at g <= 0) in `energy`. False inside the range.
bool outside_range(double gap, double range, Vec12* grad, Mat12* hess, double& energy) {
  if (gap < range && gap > 0.0) return false;
  if (grad) grad->setZero();
  if (hess) hess->setZero();
  energy = gap < range ? std::numeric_limits<double>::infinity() : 0.0;
  return true;
}

// Whether the boxes of a pair's two primitives (vertices 0 .. split - 1 and split .. 3 of x) lie
// farther apart than thickness + dhat: the boxes' distance bounds the primitives' from below, so
// such a pair is out of range, decided without its distance type (most candidates are: the lists
// hold pairs several ranges apart, self_contact_term.hpp). The margin keeps every pair the exact
// test would call active.
bool boxes_beyond(const Vec12& x, int split, double reach) {
  const double beyond = reach + kBoxRoundingMargin;
  return split_boxes_squared_distance({x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9)}, split) >
         beyond * beyond;
}

// Helmert's contrasts: K x (K - 1), orthonormal columns orthogonal to (1, ..., 1).
template <int K>
Eigen::Matrix<double, K, K - 1> helmert_contrasts() {
  Eigen::Matrix<double, K, K - 1> V = Eigen::Matrix<double, K, K - 1>::Zero();
  for (int j = 0; j < K - 1; ++j) {
    const double scale = 1.0 / std::sqrt((j + 1.0) * (j + 2.0));
    for (int i = 0; i <= j; ++i) V(i, j) = scale;
    V(j + 1, j) = -(j + 1.0) * scale;
  }
  return V;
}

// H <- project_psd<12>(H) for an H that vanishes outside the K vertices `vertices` and on
// translations, computed in their 3(K - 1) translation-free coordinates (the header says why the
// two agree). An H that is already positive semi-definite is left as it is.
template <int K>
void project_on_vertices(Mat12& H, const std::array<int, 4>& vertices) {
  constexpr int D = 3 * K;
  constexpr int R = 3 * (K - 1);
  const Eigen::Matrix<double, K, K - 1> V = helmert_contrasts<K>();
  Eigen::Matrix<double, D, R> Q;
  Eigen::Matrix<double, D, D> sub;
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K - 1; ++b) Q.template block<3, 3>(3 * a, 3 * b) = V(a, b) * Mat3::Identity();
    for (int b = 0; b < K; ++b)
      sub.template block<3, 3>(3 * a, 3 * b) = H.block<3, 3>(3 * vertices[a], 3 * vertices[b]);
  }
  const Eigen::Matrix<double, R, R> reduced = Q.transpose() * sub * Q;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, R, R>> eig(reduced);
  if (eig.eigenvalues().minCoeff() >= 0.0) return;
  const Eigen::Matrix<double, D, R> QV = Q * eig.eigenvectors();
  sub = QV * eig.eigenvalues().cwiseAbs().asDiagonal() * QV.transpose();
  H.setZero();
  for (int a = 0; a < K; ++a)
    for (int b = 0; b < K; ++b)
      H.block<3, 3>(3 * vertices[a], 3 * vertices[b]) = sub.template block<3, 3>(3 * a, 3 * b);
}

// The vertices a pair's energy depends on (the first `count` of `vertices`), where its Hessian is
// projected.
struct Support {
  std::array<int, 4> vertices = {0, 1, 2, 3};
  int count = 4;
};

// The PT barrier's energy, with its gradient and exact Hessian where given, and the Hessian's
// support.
double point_triangle_barrier(const PointTriangleBarrier& k, const Vec12& x, Vec12* grad, Mat12* hess,
                              Support* support) {
  const GapBarrier barrier{{k.stiffness, k.range}, k.thickness};
  const PointTriangleDistanceType type = point_triangle_distance_type(x);
  const double s = point_triangle_squared_distance(x, type);
  double energy = 0.0;
  if (outside_range(barrier.gap(s), k.range, grad, hess, energy)) return energy;
  if (!grad && !hess) return barrier.scalar.barrier(barrier.gap(s));
  Vec12 grad_s;
  Mat12 hess_s;
  point_triangle_squared_distance(x, type, &grad_s, hess ? &hess_s : nullptr);
  if (support) support->count = point_triangle_distance_vertices(type, support->vertices);
  return barrier.with_derivatives(s, grad_s, &hess_s, grad, hess);
}

// The EE barrier m b, with its gradient and exact Hessian by the product rule where given, and the
// Hessian's support (all four vertices where the mollifier is below 1).
double edge_edge_barrier(const EdgeEdgeBarrier& k, const Vec12& x, Vec12* grad, Mat12* hess, Support* support) {
  const GapBarrier barrier{{k.stiffness, k.range}, k.thickness};
  const EdgeEdgeDistanceType type = edge_edge_distance_type(x);
  const double s = edge_edge_squared_distance(x, type);
  double energy = 0.0;
  if (outside_range(barrier.gap(s), k.range, grad, hess, energy)) return energy;
  const bool mollified = edge_edge_cross_squared_norm(x) < k.mollifier_threshold;
  const double b = barrier.scalar.barrier(barrier.gap(s));
  if (!grad && !hess) return mollified ? edge_edge_mollifier(x, k.mollifier_threshold) * b : b;
  Vec12 grad_s;
  Mat12 hess_s;
  edge_edge_squared_distance(x, type, &grad_s, hess ? &hess_s : nullptr);
  if (!mollified) {
    if (support) support->count = edge_edge_distance_vertices(type, support->vertices);
    return barrier.with_derivatives(s, grad_s, &hess_s, grad, hess);
  }
  Vec12 grad_b, grad_m;
  Mat12 hess_b, hess_m;
  barrier.with_derivatives(s, grad_s, &hess_s, &grad_b, hess ? &hess_b : nullptr);
  const double m = edge_edge_mollifier(x, k.mollifier_threshold, &grad_m, hess ? &hess_m : nullptr);
  if (grad) *grad = m * grad_b + b * grad_m;
  if (hess) {
    const Mat12 cross = grad_m * grad_b.transpose();
    *hess = m * hess_b + cross + cross.transpose() + b * hess_m;
  }
  return m * b;
}

// The frame from the closest points' weights w at x; `fallback` is the normal's direction where the
// closest points coincide.
ContactTangentFrame tangent_frame(const Vec12& x, const Eigen::Vector4d& w, const Vec3& fallback) {
  Vec3 n = closest_points_difference(x, w);
  if (!(n.squaredNorm() > 0.0)) n = fallback;
  if (!(n.squaredNorm() > 0.0)) n = Vec3::UnitZ();
  n.normalize();
  return {tangent_basis(n), w, n};
}

}  // namespace

void project_translation_invariant_psd(Mat12& H, const std::array<int, 4>& vertices, int count) {
  if (H.isZero(0.0)) return;
  if (count == 2)
    project_on_vertices<2>(H, vertices);
  else if (count == 3)
    project_on_vertices<3>(H, vertices);
  else
    project_on_vertices<4>(H, vertices);
}

bool PointTriangleBarrier::active(const Vec& x) const {
  if (boxes_beyond(x, 1, thickness + range)) return false;
  return std::sqrt(point_triangle_squared_distance(x, point_triangle_distance_type(x))) - thickness < range;
}
double PointTriangleBarrier::energy(const Vec& x) const {
  return point_triangle_barrier(*this, x, nullptr, nullptr, nullptr);
}
double PointTriangleBarrier::gradient(const Vec& x, Vec& g) const {
  return point_triangle_barrier(*this, x, &g, nullptr, nullptr);
}
void PointTriangleBarrier::hessian(const Vec& x, Mat& H, bool project) const {
  Support support;
  point_triangle_barrier(*this, x, nullptr, &H, &support);
  if (project) project_translation_invariant_psd(H, support.vertices, support.count);
}
void PointTriangleBarrier::hessian_pair(const Vec& x, Mat& exact, Mat& projected) const {
  Support support;
  point_triangle_barrier(*this, x, nullptr, &exact, &support);
  projected = exact;
  project_translation_invariant_psd(projected, support.vertices, support.count);
}

bool EdgeEdgeBarrier::active(const Vec& x) const {
  if (boxes_beyond(x, 2, thickness + range)) return false;
  return std::sqrt(edge_edge_squared_distance(x, edge_edge_distance_type(x))) - thickness < range;
}
double EdgeEdgeBarrier::energy(const Vec& x) const { return edge_edge_barrier(*this, x, nullptr, nullptr, nullptr); }
double EdgeEdgeBarrier::gradient(const Vec& x, Vec& g) const {
  return edge_edge_barrier(*this, x, &g, nullptr, nullptr);
}
void EdgeEdgeBarrier::hessian(const Vec& x, Mat& H, bool project) const {
  Support support;
  edge_edge_barrier(*this, x, nullptr, &H, &support);
  if (project) project_translation_invariant_psd(H, support.vertices, support.count);
}
void EdgeEdgeBarrier::hessian_pair(const Vec& x, Mat& exact, Mat& projected) const {
  Support support;
  edge_edge_barrier(*this, x, nullptr, &exact, &support);
  projected = exact;
  project_translation_invariant_psd(projected, support.vertices, support.count);
}

Eigen::Vector2d ContactTangentFrame::tangent_displacement(const Vec12& x, const Vec12& x_start) const {
  Vec3 relative = Vec3::Zero();
  for (int k = 0; k < 4; ++k) relative += weights[k] * (x.segment<3>(3 * k) - x_start.segment<3>(3 * k));
  return basis.transpose() * relative;
}

Eigen::Matrix<double, 2, 12> ContactTangentFrame::displacement_jacobian() const {
  Eigen::Matrix<double, 2, 12> J;
  for (int k = 0; k < 4; ++k) J.block<2, 3>(0, 3 * k) = weights[k] * basis.transpose();
  return J;
}

ContactTangentFrame point_triangle_tangent_frame(const Vec12& x_start) {
  const PointTriangleDistanceType type = point_triangle_distance_type(x_start);
  const Vec3 t0 = x_start.segment<3>(3);
  const Vec3 normal = (x_start.segment<3>(6) - t0).cross(x_start.segment<3>(9) - t0);
  return tangent_frame(x_start, point_triangle_closest_weights(x_start, type), normal);
}

ContactTangentFrame edge_edge_tangent_frame(const Vec12& x_start) {
  const EdgeEdgeDistanceType type = edge_edge_distance_type(x_start);
  const Vec3 normal =
      (x_start.segment<3>(3) - x_start.segment<3>(0)).cross(x_start.segment<3>(9) - x_start.segment<3>(6));
  return tangent_frame(x_start, edge_edge_closest_weights(x_start, type), normal);
}

}  // namespace fnopt
