#pragma once
// Squared distances between cloth primitives for self-contact (docs/design.md §14), in the style of
// IPC (Li et al. 2020, "Incremental Potential Contact", §4) and C-IPC (Li et al. 2021,
// "Codimensional Incremental Potential Contact"): point-triangle (PT) and edge-edge (EE), each with
// its gradient and Hessian in the 12 coordinates of its four vertices, x = (p, t0, t1, t2) for PT
// and x = (ea0, ea1, eb0, eb1) for EE (vertex k at x[3k..3k+2]).
//
// Distance types. The closest points of the two primitives lie on a pair of features; the distance
// TYPE names them, and within a type the squared distance s is one closed form:
//   point-point  (P_T0.., EA0_EB0..):  s = |r|^2,                       r = a - b;
//   point-edge   (P_E0.., EA_EB0..):   s = |r|^2 - (r.e)^2 / |e|^2,     r = p - e0, e = e1 - e0
//                                      (the distance to the edge's line);
//   point-plane  (P_T):                s = (r.n)^2 / |n|^2,  n = u x v, r = p - t0, u = t1 - t0, v = t2 - t0;
//   edge-edge    (EA_EB):              s = (r.n)^2 / |n|^2,  n = u x v, r = eb0 - ea0, u = ea1 - ea0,
//                                      v = eb1 - eb0 (the distance between the two lines).
// The type is decided from the closest points' parameters: the projection of p on the triangle's
// plane (barycentric beta1, beta2) and the two lines' closest parameters (s, t). Where they lie
// inside the triangle or both inside [0, 1], the plane or line-line type; otherwise the minimum
// of the convex quadratic |point on A - point on B|^2 over the parameter domain lies on the
// domain's boundary, so it is the smallest of the point-segment distances of the boundary's
// features (three for PT, four for EE), each point-point or point-edge by its segment parameter.
// Nearly parallel edges (|u x v|^2 <= 1e-16 |u|^2 |v|^2) and degenerate triangles take that
// boundary route too: there the line-line and plane formulas divide by nearly zero, and the
// boundary minimum differs from the true one by at most that sine (1e-8) times the edge length.
//
// Smoothness. Within a type s is a rational function of x, smooth wherever |e|^2 or |n|^2 does not
// vanish. Across a type boundary the two closed forms agree in value and gradient (both equal the
// true squared distance min |a - b|^2 with the same unique closest points, whose gradient is
// continuous by Danskin's theorem), so s is C^1 and its Hessian jumps. Where the closest points
// are not unique (parallel edges whose projections overlap, a point above a degenerate triangle)
// s is only continuous: EE's mollifier (below) switches the barrier off there.
//
// EE mollifier (IPC §4.3). With c = |u x v|^2 and eps_x = 1e-3 |u_rest|^2 |v_rest|^2,
//   m(c) = -(c/eps_x)^2 + 2 c/eps_x   (c < eps_x),   1   (c >= eps_x);
//   m'(c) = 2 (1 - c/eps_x)/eps_x,   m''(c) = -2/eps_x^2   (c < eps_x; 0 beyond),
// C^1 at c = eps_x and zero with its gradient at c = 0 (grad c = 0 there); the EE barrier is
// m(x) b(d(x)) (self_contact_kernel.hpp).
#include <Eigen/Core>
#include <array>

namespace fnopt {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

// The feature pair of a point p and a triangle (t0, t1, t2): a triangle vertex (P_Tk: p and tk), a
// triangle edge (P_E0: t0t1, P_E1: t1t2, P_E2: t2t0) or its interior (P_T: the plane).
enum class PointTriangleDistanceType { P_T0, P_T1, P_T2, P_E0, P_E1, P_E2, P_T };
// The feature pair of edges a = (ea0, ea1) and b = (eb0, eb1): two end points (EAi_EBj), an end
// point of one and the other edge's line (EA_EBj: eb_j and a; EAi_EB: ea_i and b) or both lines'
// interiors (EA_EB).
enum class EdgeEdgeDistanceType { EA0_EB0, EA0_EB1, EA1_EB0, EA1_EB1, EA_EB0, EA_EB1, EA0_EB, EA1_EB, EA_EB };

// The type of the closest points of x = (p, t0, t1, t2), and of x = (ea0, ea1, eb0, eb1).
PointTriangleDistanceType point_triangle_distance_type(const Vec12& x);
EdgeEdgeDistanceType edge_edge_distance_type(const Vec12& x);

// The squared distance of `type`'s closed form at x, with its gradient and Hessian in x where
// given (nullptr: not computed). Exact in closed form; no allocation.
double point_triangle_squared_distance(const Vec12& x, PointTriangleDistanceType type, Vec12* gradient = nullptr,
                                       Mat12* hessian = nullptr);
double edge_edge_squared_distance(const Vec12& x, EdgeEdgeDistanceType type, Vec12* gradient = nullptr,
                                  Mat12* hessian = nullptr);

// The stencil's vertices (indices 0..3, increasing) that `type`'s closed form depends on: the first
// `count` entries of `vertices`, count (returned) 2 for point-point, 3 for point-edge, else 4.
int point_triangle_distance_vertices(PointTriangleDistanceType type, std::array<int, 4>& vertices);
int edge_edge_distance_vertices(EdgeEdgeDistanceType type, std::array<int, 4>& vertices);

// The closest points' weights w (4 per pair): sum_k w_k x_k = (closest point of the point or of edge
// a) - (closest point of the triangle or of edge b), for the closest points of `type`. Each
// primitive's weights are its closest point's barycentric coordinates (signed: + for the point or
// edge a, - for the triangle or edge b), so they sum to zero and a common translation of all four
// vertices leaves sum_k w_k x_k unchanged.
Eigen::Vector4d point_triangle_closest_weights(const Vec12& x, PointTriangleDistanceType type);
Eigen::Vector4d edge_edge_closest_weights(const Vec12& x, EdgeEdgeDistanceType type);
// sum_k w_k x_k: the vector from the second primitive's closest point to the first's, for weights w
// of the closest points above.
Eigen::Vector3d closest_points_difference(const Vec12& x, const Eigen::Vector4d& w);

// eps_x = 1e-3 |ea1 - ea0|^2 |eb1 - eb0|^2 at the rest positions x_rest = (ea0, ea1, eb0, eb1).
double edge_edge_mollifier_threshold(const Vec12& x_rest);
// c = |(ea1 - ea0) x (eb1 - eb0)|^2, with its gradient and Hessian where given.
double edge_edge_cross_squared_norm(const Vec12& x, Vec12* gradient = nullptr, Mat12* hessian = nullptr);
// m(c(x)) on the threshold eps_x (> 0), with its gradient and Hessian where given (both zero for
// c >= eps_x, where m = 1).
double edge_edge_mollifier(const Vec12& x, double threshold, Vec12* gradient = nullptr, Mat12* hessian = nullptr);

}  // namespace fnopt
