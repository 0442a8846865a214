#include <fnopt/contact/primitive_distance.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>

namespace fnopt {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// sin^2 of the angle below which two edges count as parallel and a triangle as degenerate (the
// header says why they take the boundary route).
constexpr double kParallelSineSquared = 1e-16;

Vec3 vertex_of(const Vec12& x, int k) { return x.segment<3>(3 * k); }

// [a]_x, the matrix of a x (.).
Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// The closed forms take difference vectors y_i = x_plus - x_minus of the stencil's vertices.
struct Difference {
  int plus, minus;
};

// The closed form behind a distance type, on the stencil's vertices (indices 0..3):
// point-point (a, b), point-edge (p, e0, e1), point-plane (p, t0, t1, t2), line-line (a0, a1, b0, b1).
enum class FeatureKind { kPointPoint, kPointEdge, kPointPlane, kLineLine };
struct FeaturePair {
  FeatureKind kind;
  std::array<int, 4> vertex;
};

FeaturePair feature_pair(PointTriangleDistanceType type) {
  using T = PointTriangleDistanceType;
  using K = FeatureKind;
  switch (type) {
    case T::P_T0:
      return {K::kPointPoint, {0, 1, 0, 0}};
    case T::P_T1:
      return {K::kPointPoint, {0, 2, 0, 0}};
    case T::P_T2:
      return {K::kPointPoint, {0, 3, 0, 0}};
    case T::P_E0:
      return {K::kPointEdge, {0, 1, 2, 0}};
    case T::P_E1:
      return {K::kPointEdge, {0, 2, 3, 0}};
    case T::P_E2:
      return {K::kPointEdge, {0, 3, 1, 0}};
    case T::P_T:
      break;
  }
  return {K::kPointPlane, {0, 1, 2, 3}};
}

FeaturePair feature_pair(EdgeEdgeDistanceType type) {
  using T = EdgeEdgeDistanceType;
  using K = FeatureKind;
  switch (type) {
    case T::EA0_EB0:
      return {K::kPointPoint, {0, 2, 0, 0}};
    case T::EA0_EB1:
      return {K::kPointPoint, {0, 3, 0, 0}};
    case T::EA1_EB0:
      return {K::kPointPoint, {1, 2, 0, 0}};
    case T::EA1_EB1:
      return {K::kPointPoint, {1, 3, 0, 0}};
    case T::EA_EB0:
      return {K::kPointEdge, {2, 0, 1, 0}};
    case T::EA_EB1:
      return {K::kPointEdge, {3, 0, 1, 0}};
    case T::EA0_EB:
      return {K::kPointEdge, {0, 2, 3, 0}};
    case T::EA1_EB:
      return {K::kPointEdge, {1, 2, 3, 0}};
    case T::EA_EB:
      break;
  }
  return {K::kLineLine, {0, 1, 2, 3}};
}

// s = |r|^2: gradient 2r, Hessian 2I.
double point_point_local(const std::array<Vec3, 1>& y, Eigen::Matrix<double, 3, 1>* g, Mat3* H) {
  if (g) *g = 2.0 * y[0];
  if (H) *H = 2.0 * Mat3::Identity();
  return y[0].squaredNorm();
}

// s = |q|^2 for r = p - e0 and e = e1 - e0, with t = r.e/|e|^2 and q = r - t e (the perpendicular
// from the line, which avoids the cancellation of |r|^2 - (r.e)^2/|e|^2):
//   ds/dr = 2q,  ds/de = -2t q,
//   H_rr = 2 (I - e e^T/|e|^2),  H_re = -2 e (q - t e)^T/|e|^2 - 2t I,
//   H_ee = 2t^2 I - 2 (q - t e)(q - t e)^T/|e|^2.
double point_line_local(const std::array<Vec3, 2>& y, Eigen::Matrix<double, 6, 1>* g, Eigen::Matrix<double, 6, 6>* H) {
  const Vec3& r = y[0];
  const Vec3& e = y[1];
  const double ee = e.squaredNorm();
  const double t = r.dot(e) / ee;
  const Vec3 q = r - t * e;
  if (g) *g << 2.0 * q, -2.0 * t * q;
  if (H) {
    const Vec3 w = q - t * e;  // dt/de = w/|e|^2
    const Mat3 H_re = -2.0 / ee * e * w.transpose() - 2.0 * t * Mat3::Identity();
    H->topLeftCorner<3, 3>() = 2.0 * (Mat3::Identity() - e * e.transpose() / ee);
    H->topRightCorner<3, 3>() = H_re;
    H->bottomLeftCorner<3, 3>() = H_re.transpose();
    H->bottomRightCorner<3, 3>() = 2.0 * t * t * Mat3::Identity() - 2.0 / ee * w * w.transpose();
  }
  return q.squaredNorm();
}

// s = f^2/c with n = u x v, f = r.n, c = |n|^2 (point-plane and line-line). In (r, n):
//   ds/dr = (2f/c) n,  ds/dn = (2f/c)(r - (f/c) n),
//   H_rr = (2/c) n n^T,  H_rn = (2/c)(n r^T + f I) - (4f/c^2) n n^T,
//   H_nn = (2/c) r r^T - (4f/c^2)(r n^T + n r^T) - (2f^2/c^2) I + (8f^2/c^3) n n^T;
// then through n: dn/du = -[v]_x, dn/dv = [u]_x, and n's second derivative contracted with ds/dn
// adds -[ds/dn]_x to the (u, v) block (g.(u x v) = -u^T [g]_x v).
double point_plane_local(const std::array<Vec3, 3>& y, Eigen::Matrix<double, 9, 1>* g, Eigen::Matrix<double, 9, 9>* H) {
  const Vec3& r = y[0];
  const Vec3 n = y[1].cross(y[2]);
  const double c = n.squaredNorm();
  const double f = r.dot(n);
  if (!g && !H) return f * f / c;
  const Vec3 s_n = 2.0 * f / c * (r - f / c * n);
  const Mat3 n_u = -cross_matrix(y[2]);
  const Mat3 n_v = cross_matrix(y[1]);
  if (g) *g << 2.0 * f / c * n, n_u.transpose() * s_n, n_v.transpose() * s_n;
  if (H) {
    const Mat3 nn = n * n.transpose();
    const Mat3 H_rn = 2.0 / c * (n * r.transpose() + f * Mat3::Identity()) - 4.0 * f / (c * c) * nn;
    const Mat3 H_nn = 2.0 / c * r * r.transpose() - 4.0 * f / (c * c) * (r * n.transpose() + n * r.transpose()) -
                      2.0 * f * f / (c * c) * Mat3::Identity() + 8.0 * f * f / (c * c * c) * nn;
    const Mat3 H_uv = n_u.transpose() * H_nn * n_v - cross_matrix(s_n);
    H->block<3, 3>(0, 0) = 2.0 / c * nn;
    H->block<3, 3>(0, 3) = H_rn * n_u;
    H->block<3, 3>(0, 6) = H_rn * n_v;
    H->block<3, 3>(3, 3) = n_u.transpose() * H_nn * n_u;
    H->block<3, 3>(3, 6) = H_uv;
    H->block<3, 3>(6, 6) = n_v.transpose() * H_nn * n_v;
    H->block<3, 3>(3, 0) = H->block<3, 3>(0, 3).transpose();
    H->block<3, 3>(6, 0) = H->block<3, 3>(0, 6).transpose();
    H->block<3, 3>(6, 3) = H_uv.transpose();
  }
  return f * f / c;
}

// c = |n|^2, n = u x v: dc/du = (dn/du)^T 2n, dc/dv = (dn/dv)^T 2n, Hessian 2 J^T J plus -[2n]_x in
// the (u, v) block (as in point_plane_local).
double cross_squared_local(const std::array<Vec3, 2>& y, Eigen::Matrix<double, 6, 1>* g,
                           Eigen::Matrix<double, 6, 6>* H) {
  const Vec3 n = y[0].cross(y[1]);
  const Mat3 n_u = -cross_matrix(y[1]);
  const Mat3 n_v = cross_matrix(y[0]);
  if (g) *g << 2.0 * n_u.transpose() * n, 2.0 * n_v.transpose() * n;
  if (H) {
    const Mat3 H_uv = 2.0 * n_u.transpose() * n_v - cross_matrix(2.0 * n);
    H->topLeftCorner<3, 3>() = 2.0 * n_u.transpose() * n_u;
    H->topRightCorner<3, 3>() = H_uv;
    H->bottomLeftCorner<3, 3>() = H_uv.transpose();
    H->bottomRightCorner<3, 3>() = 2.0 * n_v.transpose() * n_v;
  }
  return n.squaredNorm();
}

// Evaluates local(y, gy, Hy) on the differences y_i = x_plus - x_minus and maps its derivatives to
// the stencil's 12 coordinates (g = A^T gy, H = A^T Hy A, A the 0/+-1 difference map), overwriting.
template <int M, class Local>
double on_differences(const Vec12& x, const std::array<Difference, M>& d, Local&& local, Vec12* g, Mat12* H) {
  std::array<Vec3, M> y;
  for (int i = 0; i < M; ++i) y[i] = vertex_of(x, d[i].plus) - vertex_of(x, d[i].minus);
  Eigen::Matrix<double, 3 * M, 1> gy;
  Eigen::Matrix<double, 3 * M, 3 * M> Hy;
  const double value = local(y, g ? &gy : nullptr, H ? &Hy : nullptr);
  if (g) {
    g->setZero();
    for (int i = 0; i < M; ++i) {
      g->segment<3>(3 * d[i].plus) += gy.template segment<3>(3 * i);
      g->segment<3>(3 * d[i].minus) -= gy.template segment<3>(3 * i);
    }
  }
  if (H) {
    H->setZero();
    for (int i = 0; i < M; ++i)
      for (int j = 0; j < M; ++j) {
        const Mat3 block = Hy.template block<3, 3>(3 * i, 3 * j);
        H->block<3, 3>(3 * d[i].plus, 3 * d[j].plus) += block;
        H->block<3, 3>(3 * d[i].plus, 3 * d[j].minus) -= block;
        H->block<3, 3>(3 * d[i].minus, 3 * d[j].plus) -= block;
        H->block<3, 3>(3 * d[i].minus, 3 * d[j].minus) += block;
      }
  }
  return value;
}

double feature_squared_distance(const Vec12& x, const FeaturePair& f, Vec12* g, Mat12* H) {
  const auto& v = f.vertex;
  switch (f.kind) {
    case FeatureKind::kPointPoint:
      return on_differences<1>(x, {{{v[0], v[1]}}}, point_point_local, g, H);
    case FeatureKind::kPointEdge:
      return on_differences<2>(x, {{{v[0], v[1]}, {v[2], v[1]}}}, point_line_local, g, H);
    case FeatureKind::kPointPlane:
      return on_differences<3>(x, {{{v[0], v[1]}, {v[2], v[1]}, {v[3], v[1]}}}, point_plane_local, g, H);
    case FeatureKind::kLineLine:
      break;
  }
  // r = b0 - a0, u = a1 - a0, v = b1 - b0.
  return on_differences<3>(x, {{{v[2], v[0]}, {v[1], v[0]}, {v[3], v[2]}}}, point_plane_local, g, H);
}

// The parameter t of the point of segment (e0, e1) closest to p, in [0, 1] (0 for a point-size
// segment), and that point's squared distance.
struct SegmentPoint {
  double t, squared_distance;
};
SegmentPoint closest_on_segment(const Vec3& p, const Vec3& e0, const Vec3& e1) {
  const Vec3 e = e1 - e0;
  const double ee = e.squaredNorm();
  const double t = ee > 0.0 ? std::clamp((p - e0).dot(e) / ee, 0.0, 1.0) : 0.0;
  return {t, (p - (e0 + t * e)).squaredNorm()};
}

// The boundary candidates of a type decision: a point against a segment, and the types of the
// three outcomes (the segment's start, its end, its interior).
template <class Type>
struct PointSegmentCandidate {
  int point, e0, e1;
  Type at_start, at_end, inside;
};

// The type of the closest of the candidates (the first on a tie).
template <class Type, std::size_t N>
Type closest_candidate(const Vec12& x, const std::array<PointSegmentCandidate<Type>, N>& candidates) {
  double best = std::numeric_limits<double>::infinity();
  Type type = candidates[0].at_start;
  for (const auto& c : candidates) {
    const SegmentPoint s = closest_on_segment(vertex_of(x, c.point), vertex_of(x, c.e0), vertex_of(x, c.e1));
    if (!(s.squared_distance < best)) continue;
    best = s.squared_distance;
    type = s.t <= 0.0 ? c.at_start : (s.t >= 1.0 ? c.at_end : c.inside);
  }
  return type;
}

// (s, t) of the closest points ea0 + s u and eb0 + t v of the two lines (r = eb0 - ea0, n = u x v):
//   s = (r x v).n/|n|^2,  t = (r x u).n/|n|^2.
Eigen::Vector2d line_line_parameters(const Vec12& x) {
  const Vec3 u = vertex_of(x, 1) - vertex_of(x, 0);
  const Vec3 v = vertex_of(x, 3) - vertex_of(x, 2);
  const Vec3 r = vertex_of(x, 2) - vertex_of(x, 0);
  const Vec3 n = u.cross(v);
  const double nn = n.squaredNorm();
  return {r.cross(v).dot(n) / nn, r.cross(u).dot(n) / nn};
}

// (beta1, beta2) of p's projection t0 + beta1 u + beta2 v on the triangle's plane (r = p - t0):
//   beta1 = (r x v).n/|n|^2,  beta2 = (u x r).n/|n|^2.
Eigen::Vector2d plane_barycentric(const Vec12& x) {
  const Vec3 u = vertex_of(x, 2) - vertex_of(x, 1);
  const Vec3 v = vertex_of(x, 3) - vertex_of(x, 1);
  const Vec3 r = vertex_of(x, 0) - vertex_of(x, 1);
  const Vec3 n = u.cross(v);
  const double nn = n.squaredNorm();
  return {r.cross(v).dot(n) / nn, u.cross(r).dot(n) / nn};
}

// Whether |u x v|^2 is above the parallel threshold for the edges (x_a1 - x_a0) and (x_b1 - x_b0).
bool not_parallel(const Vec12& x, int a0, int a1, int b0, int b1) {
  const Vec3 u = vertex_of(x, a1) - vertex_of(x, a0);
  const Vec3 v = vertex_of(x, b1) - vertex_of(x, b0);
  return u.cross(v).squaredNorm() > kParallelSineSquared * u.squaredNorm() * v.squaredNorm();
}

}  // namespace

PointTriangleDistanceType point_triangle_distance_type(const Vec12& x) {
  using T = PointTriangleDistanceType;
  if (not_parallel(x, 1, 2, 1, 3)) {
    const Eigen::Vector2d beta = plane_barycentric(x);
    if (beta[0] >= 0.0 && beta[1] >= 0.0 && beta[0] + beta[1] <= 1.0) return T::P_T;
  }
  static constexpr std::array<PointSegmentCandidate<T>, 3> kEdges = {{
      {0, 1, 2, T::P_T0, T::P_T1, T::P_E0},
      {0, 2, 3, T::P_T1, T::P_T2, T::P_E1},
      {0, 3, 1, T::P_T2, T::P_T0, T::P_E2},
  }};
  return closest_candidate(x, kEdges);
}

EdgeEdgeDistanceType edge_edge_distance_type(const Vec12& x) {
  using T = EdgeEdgeDistanceType;
  if (not_parallel(x, 0, 1, 2, 3)) {
    const Eigen::Vector2d st = line_line_parameters(x);
    if (st[0] >= 0.0 && st[0] <= 1.0 && st[1] >= 0.0 && st[1] <= 1.0) return T::EA_EB;
  }
  static constexpr std::array<PointSegmentCandidate<T>, 4> kEnds = {{
      {0, 2, 3, T::EA0_EB0, T::EA0_EB1, T::EA0_EB},
      {1, 2, 3, T::EA1_EB0, T::EA1_EB1, T::EA1_EB},
      {2, 0, 1, T::EA0_EB0, T::EA1_EB0, T::EA_EB0},
      {3, 0, 1, T::EA0_EB1, T::EA1_EB1, T::EA_EB1},
  }};
  return closest_candidate(x, kEnds);
}

double point_triangle_squared_distance(const Vec12& x, PointTriangleDistanceType type, Vec12* gradient,
                                       Mat12* hessian) {
  return feature_squared_distance(x, feature_pair(type), gradient, hessian);
}

double edge_edge_squared_distance(const Vec12& x, EdgeEdgeDistanceType type, Vec12* gradient, Mat12* hessian) {
  return feature_squared_distance(x, feature_pair(type), gradient, hessian);
}

namespace {

// sum_k w_k x_k = (closest point of the pair's first primitive) - (of its second): the point or edge
// a are vertices 0 (PT) or 0, 1 (EE), so a feature's point with index >= 2 is edge b's.
Eigen::Vector4d closest_weights(const Vec12& x, const FeaturePair& f) {
  const auto& v = f.vertex;
  Eigen::Vector4d w = Eigen::Vector4d::Zero();
  switch (f.kind) {
    case FeatureKind::kPointPoint:
      w[v[0]] = 1.0;
      w[v[1]] = -1.0;
      return w;
    case FeatureKind::kPointEdge: {
      const Vec3 e = vertex_of(x, v[2]) - vertex_of(x, v[1]);
      const double t = (vertex_of(x, v[0]) - vertex_of(x, v[1])).dot(e) / e.squaredNorm();
      const double sign = v[0] < 2 ? 1.0 : -1.0;
      w[v[0]] = sign;
      w[v[1]] = -sign * (1.0 - t);
      w[v[2]] = -sign * t;
      return w;
    }
    case FeatureKind::kPointPlane: {
      const Eigen::Vector2d beta = plane_barycentric(x);
      return {1.0, -(1.0 - beta[0] - beta[1]), -beta[0], -beta[1]};
    }
    case FeatureKind::kLineLine:
      break;
  }
  const Eigen::Vector2d st = line_line_parameters(x);
  return {1.0 - st[0], st[0], -(1.0 - st[1]), -st[1]};
}

// The feature pair's vertices in increasing order, and how many.
int sorted_vertices(const FeaturePair& f, std::array<int, 4>& vertices) {
  const int count = f.kind == FeatureKind::kPointPoint ? 2 : (f.kind == FeatureKind::kPointEdge ? 3 : 4);
  std::copy(f.vertex.begin(), f.vertex.begin() + count, vertices.begin());
  std::sort(vertices.begin(), vertices.begin() + count);
  return count;
}

}  // namespace

int point_triangle_distance_vertices(PointTriangleDistanceType type, std::array<int, 4>& vertices) {
  return sorted_vertices(feature_pair(type), vertices);
}

int edge_edge_distance_vertices(EdgeEdgeDistanceType type, std::array<int, 4>& vertices) {
  return sorted_vertices(feature_pair(type), vertices);
}

Eigen::Vector4d point_triangle_closest_weights(const Vec12& x, PointTriangleDistanceType type) {
  return closest_weights(x, feature_pair(type));
}

Eigen::Vector4d edge_edge_closest_weights(const Vec12& x, EdgeEdgeDistanceType type) {
  return closest_weights(x, feature_pair(type));
}

Eigen::Vector3d closest_points_difference(const Vec12& x, const Eigen::Vector4d& w) {
  Eigen::Vector3d difference = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) difference += w[k] * x.segment<3>(3 * k);
  return difference;
}

double edge_edge_mollifier_threshold(const Vec12& x_rest) {
  const double a = (vertex_of(x_rest, 1) - vertex_of(x_rest, 0)).squaredNorm();
  const double b = (vertex_of(x_rest, 3) - vertex_of(x_rest, 2)).squaredNorm();
  return 1e-3 * a * b;
}

double edge_edge_cross_squared_norm(const Vec12& x, Vec12* gradient, Mat12* hessian) {
  return on_differences<2>(x, {{{1, 0}, {3, 2}}}, cross_squared_local, gradient, hessian);
}

// m(c) = -(c/eps)^2 + 2c/eps below eps, 1 beyond; grad m = m'(c) grad c and
// hess m = m''(c) grad c grad c^T + m'(c) hess c with m' = 2(1 - c/eps)/eps, m'' = -2/eps^2.
double edge_edge_mollifier(const Vec12& x, double threshold, Vec12* gradient, Mat12* hessian) {
  if (!(edge_edge_cross_squared_norm(x) < threshold)) {
    if (gradient) gradient->setZero();
    if (hessian) hessian->setZero();
    return 1.0;
  }
  Vec12 grad_c;
  const double c = edge_edge_cross_squared_norm(x, &grad_c, hessian);
  const double ratio = c / threshold;
  const double slope = 2.0 * (1.0 - ratio) / threshold;
  if (gradient) *gradient = slope * grad_c;
  if (hessian) *hessian = slope * *hessian - 2.0 / (threshold * threshold) * grad_c * grad_c.transpose();
  return (2.0 - ratio) * ratio;
}

}  // namespace fnopt
