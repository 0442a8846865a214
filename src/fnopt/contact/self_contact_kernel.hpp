#pragma once
// Self-contact barriers of the cloth's non-adjacent primitives (docs/design.md §14), after C-IPC
// (Li et al. 2021, "Codimensional Incremental Potential Contact"): per point-triangle (PT) or
// edge-edge (EE) pair, on the gap g = d - thickness of the pair's distance d
// (primitive_distance.hpp), the obstacles' log barrier (repulsion_kernel.hpp, contact_term.hpp)
//   b(g) = -kappa (g - dhat)^2 log(g / dhat)   (0 < g < dhat),   0 (g >= dhat),   +inf (g <= 0).
// Per-stencil kernels in the style of repulsion_kernel.hpp: four vertices, x = (p, t0, t1, t2) or
// (ea0, ea1, eb0, eb1), energy, gradient and Hessian on fixed-size Eigen types.
//
// Chain rule. The closed forms give the squared distance s and its derivatives; with d = sqrt(s),
//   db/ds   = b'(g) / (2d),
//   d2b/ds2 = (b''(g) - b'(g)/d) / (4 d^2),
//   grad b  = (db/ds) grad s,   hess b = (d2b/ds2) grad s grad s^T + (db/ds) hess s.
// d2b/ds2 > 0 inside the range (b'' > 0 > b'), so the first part is positive semi-definite and
// db/ds < 0 times hess s is the indefinite one.
//
// EE mollifier (Li et al. 2020, "Incremental Potential Contact", §4.3). Nearly parallel edges make
// the line-line distance ill-conditioned and, where their projections overlap, non-smooth; the EE
// energy is m(x) b(g(x)) with IPC's mollifier m on |ea x eb|^2 (primitive_distance.hpp):
//   grad = m grad b + b grad m,   hess = m hess b + grad m grad b^T + grad b grad m^T + b hess m.
// m applies to every EE type (its point-point and point-edge ones too), as in IPC.
//
// Projection. Projected Newton (§6) replaces each negative eigenvalue of the pair's Hessian by its
// absolute value, as project_psd<12> does, but in fewer coordinates with the same result: the
// energy is translation-invariant and depends only on the type's vertices (2 for point-point, 3
// for point-edge, else 4; all 4 where the mollifier is below 1), so the Hessian vanishes on the
// other vertices and on the three common translations. With Q an orthonormal basis (Helmert's
// contrasts, times I3) of the 3(K - 1) translation-free coordinates of the type's K vertices,
// H = Q (Q^T H Q) Q^T, and projecting the 3(K-1)-square Q^T H Q by its eigen-decomposition then
// mapping back equals project_psd<12>(H) (the null space keeps eigenvalue 0). An H that is
// already positive semi-definite is returned unchanged. Inside the range the unmollified Hessian
// never is: the energy is invariant under rotations x_k -> R(theta) x_k, so along the rotation
// about a unit axis a the curvature is x'^T H x' = -g.x'' = sum_k g_k.(x_k)_perp(a), and the three
// axes' curvatures sum to 2 sum_k g_k.x_k = 2 b'(g) d < 0 (s is homogeneous of degree 2 in x).
//
// Beyond the range the energy, gradient and Hessian are exactly zero; at g <= 0 (a state the step
// filter never lets a solve reach) the energy is +inf and the gradient and Hessian are zero.
//
// Friction (IPC §5, lagged as in friction.hpp): point_triangle_tangent_frame and
// edge_edge_tangent_frame give, at the step's start x_t, the pair's closest points' weights w
// (sum_k w_k x_k = closest point of the first primitive minus that of the second,
// primitive_distance.hpp) and an orthonormal tangent basis T normal to the closest points'
// direction, so the relative tangential displacement over the step is
//   u = T^T sum_k w_k (x_k - x_t,k)   (u/dt the relative tangential velocity),
// zero for a common translation since sum_k w_k = 0. For the plane type the normal is the
// triangle's and for the line-line type ea x eb, up to sign, as in ipc-toolkit's
// point_triangle_tangent_basis and edge_edge_tangent_basis; for point-point and point-edge types
// it is the closest points' direction, as for its vertex-vertex and edge-vertex pairs.
#include <Eigen/Core>
#include <array>

#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

struct PointTriangleBarrier {
  static constexpr int kVertices = 4;
  using Vec = Vec12;
  using Mat = Mat12;

  double stiffness = 0.0;  // kappa [N/m]
  double range = 0.0;      // dhat [m]
  double thickness = 0.0;  // [m]

  // True if the pair is inside the range, g < dhat (a non-zero contribution).
  bool active(const Vec& x) const;
  double energy(const Vec& x) const;
  // Writes the gradient to g and returns the energy.
  double gradient(const Vec& x, Vec& g) const;
  // The Hessian, projected to positive semi-definite where `project`.
  void hessian(const Vec& x, Mat& H, bool project) const;
  // hessian(x, exact, false) and hessian(x, projected, true) from one evaluation.
  void hessian_pair(const Vec& x, Mat& exact, Mat& projected) const;
};

struct EdgeEdgeBarrier {
  static constexpr int kVertices = 4;
  using Vec = Vec12;
  using Mat = Mat12;

  double stiffness = 0.0;  // kappa [N/m]
  double range = 0.0;      // dhat [m]
  double thickness = 0.0;  // [m]
  // eps_x [m^4], from the rest positions by edge_edge_mollifier_threshold; 0 turns the mollifier off.
  double mollifier_threshold = 0.0;

  // True if the pair is inside the range, g < dhat (a non-zero contribution unless the edges are
  // exactly parallel, where m = 0).
  bool active(const Vec& x) const;
  double energy(const Vec& x) const;
  double gradient(const Vec& x, Vec& g) const;
  void hessian(const Vec& x, Mat& H, bool project) const;
  void hessian_pair(const Vec& x, Mat& exact, Mat& projected) const;
};

// H <- project_psd<12>(H) for the Hessian H of a translation-invariant energy of the stencil's
// vertices vertices[0..count) that is zero on the others (count 2, 3 or 4), computed in their
// 3(count - 1) translation-free coordinates (see above). An H already positive semi-definite is
// left unchanged.
void project_translation_invariant_psd(Mat12& H, const std::array<int, 4>& vertices, int count);

// The frozen frame of a pair's lagged friction at the step's start (see above).
struct ContactTangentFrame {
  Eigen::Matrix<double, 3, 2> basis;  // T, orthonormal columns normal to `normal`
  Eigen::Vector4d weights;            // w, summing to zero
  Vec3 normal;                        // unit, from the second primitive's closest point to the first's

  // u = T^T sum_k w_k (x_k - x_start,k).
  Eigen::Vector2d tangent_displacement(const Vec12& x, const Vec12& x_start) const;
  // du/dx = T^T (w^T (x) I3), constant over the step: u = J (x - x_start).
  Eigen::Matrix<double, 2, 12> displacement_jacobian() const;
};

// The frames of a PT pair x_start = (p, t0, t1, t2) and an EE pair (ea0, ea1, eb0, eb1), at their
// closest points' type at x_start. Where the closest points coincide (distance 0, never at a
// feasible state) the normal is the triangle's, or ea x eb (UnitZ if that vanishes too).
ContactTangentFrame point_triangle_tangent_frame(const Vec12& x_start);
ContactTangentFrame edge_edge_tangent_frame(const Vec12& x_start);

}  // namespace fnopt
