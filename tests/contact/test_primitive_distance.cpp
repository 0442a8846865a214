// Point-triangle and edge-edge squared distances (contact/primitive_distance.hpp): a configuration
// in each distance type, its type, its value against a brute-force minimum over the primitives'
// parameters, gradient and Hessian against central differences, invariance under rigid motions,
// symmetry under permutations of the triangle's vertices and under swapping or reversing edges,
// C^1 across a type boundary, the closest points' weights, and the EE mollifier.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include <fnopt/contact/primitive_distance.hpp>
#include <fnopt/util/types.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

using PT = PointTriangleDistanceType;
using EE = EdgeEdgeDistanceType;

Vec12 stencil(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec12 x;
  x << a, b, c, d;
  return x;
}

// The triangle (0,0,0), (1,0,0), (0,1,0) and a point in each region of its closest feature.
struct PointTriangleCase {
  PT type;
  Vec3 p;
};
const std::vector<PointTriangleCase> kPointTriangleCases = {
    {PT::P_T, Vec3(0.25, 0.3, 0.4)},   {PT::P_T0, Vec3(-0.3, -0.2, 0.1)}, {PT::P_T1, Vec3(1.3, -0.2, 0.2)},
    {PT::P_T2, Vec3(-0.2, 1.4, -0.1)}, {PT::P_E0, Vec3(0.4, -0.3, 0.2)},  {PT::P_E1, Vec3(0.7, 0.6, 0.1)},
    {PT::P_E2, Vec3(-0.3, 0.6, -0.2)},
};
Vec12 point_triangle(const Vec3& p) { return stencil(p, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)); }

// Edge a from (0,0,0) to (1,0,0) and an edge b in each region of the closest feature pair.
struct EdgeEdgeCase {
  EE type;
  Vec3 b0, b1;
};
const std::vector<EdgeEdgeCase> kEdgeEdgeCases = {
    {EE::EA_EB, Vec3(0.4, -0.6, 0.3), Vec3(0.6, 0.5, 0.35)},
    {EE::EA0_EB0, Vec3(-0.3, -0.2, 0.2), Vec3(-0.6, -0.7, 0.6)},
    {EE::EA0_EB1, Vec3(-0.6, -0.7, 0.6), Vec3(-0.3, -0.2, 0.2)},
    {EE::EA1_EB0, Vec3(1.3, -0.2, 0.2), Vec3(1.6, -0.7, 0.6)},
    {EE::EA1_EB1, Vec3(1.6, -0.7, 0.6), Vec3(1.3, -0.2, 0.2)},
    {EE::EA_EB0, Vec3(0.5, 0.15, 0.2), Vec3(0.8, 0.75, 1.0)},
    {EE::EA_EB1, Vec3(0.8, 0.75, 1.0), Vec3(0.5, 0.15, 0.2)},
    {EE::EA0_EB, Vec3(-0.3, -0.5, 0.3), Vec3(-0.3, 0.6, 0.3)},
    {EE::EA1_EB, Vec3(1.2, -0.5, 0.3), Vec3(1.3, 0.6, 0.2)},
};
Vec12 edge_edge(const EdgeEdgeCase& c) { return stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), c.b0, c.b1); }

// A random rotation and translation applied to each vertex.
struct RigidMotion {
  Mat3 rotation;
  Vec3 translation;
  Vec12 apply(const Vec12& x) const {
    Vec12 y;
    for (int k = 0; k < 4; ++k) y.segment<3>(3 * k) = rotation * x.segment<3>(3 * k) + translation;
    return y;
  }
  Vec12 rotate(const Vec12& g) const {
    Vec12 y;
    for (int k = 0; k < 4; ++k) y.segment<3>(3 * k) = rotation * g.segment<3>(3 * k);
    return y;
  }
  Mat12 rotate(const Mat12& H) const {
    Mat12 big = Mat12::Zero();
    for (int k = 0; k < 4; ++k) big.block<3, 3>(3 * k, 3 * k) = rotation;
    return big * H * big.transpose();
  }
};
RigidMotion random_motion(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return {q.normalized().toRotationMatrix(), Vec3(normal(rng), normal(rng), normal(rng))};
}

// The minimum of f over a 2-D parameter domain (inside(a, b) says which points belong to it, within
// [0, 1]^2): a 401^2 grid, then 60 rounds of a 21^2 grid over +-5 spacings around the best point.
// For the convex quadratics here (well-conditioned) the box keeps the minimizer.
double brute_force_minimum(const std::function<double(double, double)>& f,
                           const std::function<bool(double, double)>& inside) {
  double best = std::numeric_limits<double>::infinity(), best_a = 0.0, best_b = 0.0;
  auto sample = [&](double a, double b) {
    a = std::clamp(a, 0.0, 1.0);
    b = std::clamp(b, 0.0, 1.0);
    if (!inside(a, b)) return;
    const double value = f(a, b);
    if (value < best) best = value, best_a = a, best_b = b;
  };
  double spacing = 1.0 / 400.0;
  for (int i = 0; i <= 400; ++i)
    for (int j = 0; j <= 400; ++j) sample(i * spacing, j * spacing);
  for (int round = 0; round < 60; ++round) {
    const double a0 = best_a, b0 = best_b;
    for (int i = -10; i <= 10; ++i)
      for (int j = -10; j <= 10; ++j) sample(a0 + 0.5 * i * spacing, b0 + 0.5 * j * spacing);
    spacing *= 0.5;
  }
  return best;
}

double brute_force_point_triangle(const Vec12& x) {
  const Vec3 p = x.segment<3>(0), t0 = x.segment<3>(3), t1 = x.segment<3>(6), t2 = x.segment<3>(9);
  return brute_force_minimum(
      [&](double a, double b) { return (p - (t0 + a * (t1 - t0) + b * (t2 - t0))).squaredNorm(); },
      [](double a, double b) { return a + b <= 1.0; });
}

double brute_force_edge_edge(const Vec12& x) {
  const Vec3 a0 = x.segment<3>(0), a1 = x.segment<3>(3), b0 = x.segment<3>(6), b1 = x.segment<3>(9);
  return brute_force_minimum(
      [&](double s, double t) { return (a0 + s * (a1 - a0) - b0 - t * (b1 - b0)).squaredNorm(); },
      [](double, double) { return true; });
}

// A squared distance with its derivatives, at a fixed type.
using Distance = std::function<double(const Vec12&, Vec12*, Mat12*)>;

void expect_derivatives_match(const Distance& distance, const Vec12& x, const std::string& label) {
  Vec12 g;
  Mat12 H;
  const double value = distance(x, &g, &H);
  EXPECT_EQ(value, distance(x, nullptr, nullptr)) << label;
  const double eps = 1e-6;
  const Vec12 g_fd = testing::central_gradient([&](const Vec12& y) { return distance(y, nullptr, nullptr); }, x, eps);
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const Vec12& y) {
        Vec12 gy;
        distance(y, &gy, nullptr);
        return Eigen::VectorXd(gy);
      },
      x, eps);
  EXPECT_LT((g - g_fd).norm(), 1e-6 * g.norm()) << label;
  EXPECT_LT((H - H_fd).norm(), 1e-6 * H.norm()) << label;
  EXPECT_LT((H - H.transpose()).norm(), 1e-14 * H.norm()) << label;
  // Translation invariance: the gradient sums to zero over the vertices, and so do H's block rows.
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 4; ++k) sum += g.segment<3>(3 * k);
  EXPECT_LT(sum.norm(), 1e-14 * g.norm()) << label;
}

Distance point_triangle_at(PT type) {
  return [type](const Vec12& y, Vec12* g, Mat12* H) { return point_triangle_squared_distance(y, type, g, H); };
}
Distance edge_edge_at(EE type) {
  return [type](const Vec12& y, Vec12* g, Mat12* H) { return edge_edge_squared_distance(y, type, g, H); };
}

TEST(PrimitiveDistance, PointTriangleTypeValueAndDerivativesInEachType) {
  std::mt19937 rng(11);
  for (const PointTriangleCase& c : kPointTriangleCases) {
    for (int trial = 0; trial < 3; ++trial) {
      const Vec12 x = trial == 0 ? point_triangle(c.p) : random_motion(rng).apply(point_triangle(c.p));
      const std::string label = "type " + std::to_string(static_cast<int>(c.type)) + ", trial " + std::to_string(trial);
      ASSERT_EQ(point_triangle_distance_type(x), c.type) << label;
      const double s = point_triangle_squared_distance(x, c.type);
      EXPECT_NEAR(s, brute_force_point_triangle(x), 1e-12 * (1.0 + s)) << label;
      expect_derivatives_match(point_triangle_at(c.type), x, label);
    }
  }
}

TEST(PrimitiveDistance, EdgeEdgeTypeValueAndDerivativesInEachType) {
  std::mt19937 rng(12);
  for (const EdgeEdgeCase& c : kEdgeEdgeCases) {
    for (int trial = 0; trial < 3; ++trial) {
      const Vec12 x = trial == 0 ? edge_edge(c) : random_motion(rng).apply(edge_edge(c));
      const std::string label = "type " + std::to_string(static_cast<int>(c.type)) + ", trial " + std::to_string(trial);
      ASSERT_EQ(edge_edge_distance_type(x), c.type) << label;
      const double s = edge_edge_squared_distance(x, c.type);
      EXPECT_NEAR(s, brute_force_edge_edge(x), 1e-12 * (1.0 + s)) << label;
      expect_derivatives_match(edge_edge_at(c.type), x, label);
    }
  }
}

// At random configurations (any type) the closed form of the decided type is the true minimum.
TEST(PrimitiveDistance, DecidedTypeGivesTheMinimumAtRandomConfigurations) {
  std::mt19937 rng(13);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto random_point = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Vec12 x = stencil(random_point(), random_point(), random_point(), random_point());
    const double pt = point_triangle_squared_distance(x, point_triangle_distance_type(x));
    const double ee = edge_edge_squared_distance(x, edge_edge_distance_type(x));
    EXPECT_NEAR(pt, brute_force_point_triangle(x), 1e-11 * (1.0 + pt)) << trial;
    EXPECT_NEAR(ee, brute_force_edge_edge(x), 1e-11 * (1.0 + ee)) << trial;
  }
}

template <class Type>
void expect_rigid_invariance(const Vec12& x, Type type, const RigidMotion& motion, const std::string& label) {
  auto evaluate = [](const Vec12& y, Type t, Vec12* g, Mat12* H) {
    if constexpr (std::is_same_v<Type, PT>)
      return point_triangle_squared_distance(y, t, g, H);
    else
      return edge_edge_squared_distance(y, t, g, H);
  };
  Vec12 g, g_moved;
  Mat12 H, H_moved;
  const double s = evaluate(x, type, &g, &H);
  const double s_moved = evaluate(motion.apply(x), type, &g_moved, &H_moved);
  EXPECT_NEAR(s_moved, s, 1e-13 * (1.0 + s)) << label;
  EXPECT_LT((g_moved - motion.rotate(g)).norm(), 1e-12 * (1.0 + g.norm())) << label;
  EXPECT_LT((H_moved - motion.rotate(H)).norm(), 1e-11 * (1.0 + H.norm())) << label;
}

TEST(PrimitiveDistance, InvariantUnderRigidMotions) {
  std::mt19937 rng(14);
  for (int trial = 0; trial < 4; ++trial) {
    const RigidMotion motion = random_motion(rng);
    for (const PointTriangleCase& c : kPointTriangleCases) {
      const Vec12 x = point_triangle(c.p);
      ASSERT_EQ(point_triangle_distance_type(motion.apply(x)), c.type);
      expect_rigid_invariance(x, c.type, motion, "PT " + std::to_string(static_cast<int>(c.type)));
    }
    for (const EdgeEdgeCase& c : kEdgeEdgeCases) {
      const Vec12 x = edge_edge(c);
      ASSERT_EQ(edge_edge_distance_type(motion.apply(x)), c.type);
      expect_rigid_invariance(x, c.type, motion, "EE " + std::to_string(static_cast<int>(c.type)));
    }
  }
}

// x with its vertices reordered: vertex k of the result is vertex order[k] of x.
Vec12 permuted(const Vec12& x, const std::array<int, 4>& order) {
  Vec12 y;
  for (int k = 0; k < 4; ++k) y.segment<3>(3 * k) = x.segment<3>(3 * order[k]);
  return y;
}

double point_triangle_full(const Vec12& x, Vec12* g) {
  return point_triangle_squared_distance(x, point_triangle_distance_type(x), g);
}
double edge_edge_full(const Vec12& x, Vec12* g) { return edge_edge_squared_distance(x, edge_edge_distance_type(x), g); }

void expect_permutation_symmetry(const std::function<double(const Vec12&, Vec12*)>& distance, const Vec12& x,
                                 const std::array<int, 4>& order, const std::string& label) {
  Vec12 g, g_permuted;
  const double s = distance(x, &g);
  const double s_permuted = distance(permuted(x, order), &g_permuted);
  EXPECT_NEAR(s_permuted, s, 1e-14 * (1.0 + s)) << label;
  EXPECT_LT((g_permuted - permuted(g, order)).norm(), 1e-13 * (1.0 + g.norm())) << label;
}

TEST(PrimitiveDistance, SymmetricUnderTheTrianglesVertexOrder) {
  const std::array<std::array<int, 4>, 5> orders = {
      {{0, 2, 3, 1}, {0, 3, 1, 2}, {0, 2, 1, 3}, {0, 1, 3, 2}, {0, 3, 2, 1}}};
  for (const PointTriangleCase& c : kPointTriangleCases)
    for (const auto& order : orders)
      expect_permutation_symmetry(point_triangle_full, point_triangle(c.p), order,
                                  "PT " + std::to_string(static_cast<int>(c.type)));
}

TEST(PrimitiveDistance, SymmetricUnderSwappingAndReversingEdges) {
  const std::array<std::array<int, 4>, 4> orders = {{{2, 3, 0, 1}, {1, 0, 2, 3}, {0, 1, 3, 2}, {3, 2, 1, 0}}};
  for (const EdgeEdgeCase& c : kEdgeEdgeCases)
    for (const auto& order : orders)
      expect_permutation_symmetry(edge_edge_full, edge_edge(c), order,
                                  "EE " + std::to_string(static_cast<int>(c.type)));
}

// On the boundary between two types both closed forms give the same value and gradient (C^1); the
// Hessians differ.
TEST(PrimitiveDistance, TypesMeetWithEqualValueAndGradient) {
  struct Boundary {
    Vec12 x;
    Distance first, second;
  };
  const std::vector<Boundary> boundaries = {
      // p above edge t0t1: plane and edge line.
      {point_triangle(Vec3(0.4, 0.0, 0.3)), point_triangle_at(PT::P_T), point_triangle_at(PT::P_E0)},
      // p beyond t1 along the edge's normal plane: edge line and vertex.
      {point_triangle(Vec3(1.0, -0.4, 0.3)), point_triangle_at(PT::P_E0), point_triangle_at(PT::P_T1)},
      // b's closest line point at its end eb0: line-line and point-edge.
      {stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.0, 0.3), Vec3(0.5, 0.8, 0.3)), edge_edge_at(EE::EA_EB),
       edge_edge_at(EE::EA_EB0)},
  };
  for (const Boundary& b : boundaries) {
    Vec12 g1, g2;
    Mat12 H1, H2;
    const double s1 = b.first(b.x, &g1, &H1);
    const double s2 = b.second(b.x, &g2, &H2);
    EXPECT_NEAR(s1, s2, 1e-14);
    EXPECT_LT((g1 - g2).norm(), 1e-13);
    EXPECT_GT((H1 - H2).norm(), 1e-3);
  }
}

TEST(PrimitiveDistance, NearlyParallelEdgesAvoidTheLineLineForm) {
  // Overlapping parallel edges and edges 1e-9 rad apart: the closest points are not unique, and the
  // decided type's closed form still gives the minimum.
  for (double angle : {0.0, 1e-9}) {
    const Vec12 x = stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.0, 0.2), Vec3(1.3, angle, 0.2));
    const EE type = edge_edge_distance_type(x);
    EXPECT_NE(type, EE::EA_EB) << angle;
    EXPECT_NEAR(edge_edge_squared_distance(x, type), 0.04, 1e-12) << angle;
  }
}

TEST(PrimitiveDistance, ClosestWeightsGiveTheClosestPoints) {
  auto check = [](const Vec12& x, const Eigen::Vector4d& w, double s, const std::string& label) {
    EXPECT_NEAR(w.sum(), 0.0, 1e-15) << label;
    Vec3 difference = Vec3::Zero();
    for (int k = 0; k < 4; ++k) difference += w[k] * x.segment<3>(3 * k);
    EXPECT_NEAR(difference.squaredNorm(), s, 1e-14) << label;
    // The first primitive's weights are a convex combination, the second's its negative.
    EXPECT_GE(w.minCoeff(), -1.0 - 1e-15) << label;
    EXPECT_LE(w.maxCoeff(), 1.0 + 1e-15) << label;
  };
  for (const PointTriangleCase& c : kPointTriangleCases) {
    const Vec12 x = point_triangle(c.p);
    const Eigen::Vector4d w = point_triangle_closest_weights(x, c.type);
    EXPECT_EQ(w[0], 1.0);
    check(x, w, point_triangle_squared_distance(x, c.type), "PT " + std::to_string(static_cast<int>(c.type)));
  }
  for (const EdgeEdgeCase& c : kEdgeEdgeCases) {
    const Vec12 x = edge_edge(c);
    const Eigen::Vector4d w = edge_edge_closest_weights(x, c.type);
    EXPECT_NEAR(w[0] + w[1], 1.0, 1e-15);
    check(x, w, edge_edge_squared_distance(x, c.type), "EE " + std::to_string(static_cast<int>(c.type)));
  }
}

TEST(PrimitiveDistance, DistanceVerticesNameTheDependence) {
  for (const PointTriangleCase& c : kPointTriangleCases) {
    std::array<int, 4> vertices;
    const int count = point_triangle_distance_vertices(c.type, vertices);
    Vec12 g;
    point_triangle_squared_distance(point_triangle(c.p), c.type, &g);
    for (int k = 0; k < 4; ++k) {
      const bool used = std::find(vertices.begin(), vertices.begin() + count, k) != vertices.begin() + count;
      EXPECT_EQ(used, !g.segment<3>(3 * k).isZero(0.0)) << static_cast<int>(c.type) << " vertex " << k;
    }
  }
  for (const EdgeEdgeCase& c : kEdgeEdgeCases) {
    std::array<int, 4> vertices;
    const int count = edge_edge_distance_vertices(c.type, vertices);
    Vec12 g;
    edge_edge_squared_distance(edge_edge(c), c.type, &g);
    for (int k = 0; k < 4; ++k) {
      const bool used = std::find(vertices.begin(), vertices.begin() + count, k) != vertices.begin() + count;
      EXPECT_EQ(used, !g.segment<3>(3 * k).isZero(0.0)) << static_cast<int>(c.type) << " vertex " << k;
    }
  }
}

// Edge a along x; edge b at height 0.2 turned by `angle` in the xy-plane, crossing a's middle.
Vec12 turned_edges(double angle) {
  const Vec3 direction(std::cos(angle), std::sin(angle), 0.0);
  const Vec3 middle(0.5, 0.0, 0.2);
  return stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), middle - 0.4 * direction, middle + 0.4 * direction);
}

TEST(EdgeEdgeMollifier, ThresholdFromRestLengths) {
  const Vec12 rest = stencil(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 0.5));
  EXPECT_NEAR(edge_edge_mollifier_threshold(rest), 1e-3 * 4.0 * 0.25, 1e-18);
}

TEST(EdgeEdgeMollifier, DerivativesMatchFiniteDifferences) {
  const double threshold = edge_edge_mollifier_threshold(turned_edges(0.0));  // 6.4e-4
  for (double angle : {0.005, 0.02, 0.025, 0.3}) {
    const Vec12 x = turned_edges(angle);
    const Distance cross = [](const Vec12& y, Vec12* g, Mat12* H) { return edge_edge_cross_squared_norm(y, g, H); };
    expect_derivatives_match(cross, x, "c at angle " + std::to_string(angle));
    const double c = edge_edge_cross_squared_norm(x);
    EXPECT_NEAR(c, std::pow(0.8 * std::sin(angle), 2), 1e-15);
    Vec12 g;
    Mat12 H;
    const double m = edge_edge_mollifier(x, threshold, &g, &H);
    if (c >= threshold) {
      EXPECT_EQ(m, 1.0);
      EXPECT_TRUE(g.isZero(0.0));
      EXPECT_TRUE(H.isZero(0.0));
      continue;
    }
    const double ratio = c / threshold;
    EXPECT_NEAR(m, 2.0 * ratio - ratio * ratio, 1e-15);
    const Distance mollifier = [threshold](const Vec12& y, Vec12* gy, Mat12* Hy) {
      return edge_edge_mollifier(y, threshold, gy, Hy);
    };
    expect_derivatives_match(mollifier, x, "m at angle " + std::to_string(angle));
  }
}

TEST(EdgeEdgeMollifier, VanishesWithItsGradientForParallelEdges) {
  Vec12 g;
  EXPECT_EQ(edge_edge_mollifier(turned_edges(0.0), 1e-3, &g), 0.0);
  EXPECT_TRUE(g.isZero(0.0));
}

}  // namespace
}  // namespace fnopt
