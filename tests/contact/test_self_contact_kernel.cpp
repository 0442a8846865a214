// Self-contact barriers (contact/self_contact_kernel.hpp): point-triangle and edge-edge pairs in each
// distance type at chosen gaps; exact zeros at and beyond the range, +inf at contact, gradient and
// Hessian against central differences (the mollified EE pair of nearly parallel edges included),
// the projected Hessian positive semi-definite and equal to project_psd<12>, rigid motions, and the
// friction frame: orthonormal tangents normal to the contact normal, zero slip for a translation.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fnopt/cloth/psd_projection.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

using PT = PointTriangleDistanceType;
using EE = EdgeEdgeDistanceType;

constexpr double kRange = 0.1;       // dhat
constexpr double kThickness = 0.02;  // the distance of zero gap
const PointTriangleBarrier kPointTriangle{3.0, kRange, kThickness};

Vec12 stencil(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec12 x;
  x << a, b, c, d;
  return x;
}

// A point at distance d from the triangle (0,0,0), (1,0,0), (0,1,0): the foot on the closest
// feature plus d times a unit direction in that feature's normal cone.
struct PointTriangleContact {
  PT type;
  Vec3 foot, direction;
  Vec12 at(double d) const {
    return stencil(foot + d * direction.normalized(), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  }
};
const std::vector<PointTriangleContact> kPointTriangleContacts = {
    {PT::P_T, Vec3(0.25, 0.3, 0), Vec3(0, 0, 1)},   {PT::P_T0, Vec3(0, 0, 0), Vec3(-1, -1, 0.5)},
    {PT::P_T1, Vec3(1, 0, 0), Vec3(1, -0.5, 0.3)},  {PT::P_T2, Vec3(0, 1, 0), Vec3(-0.5, 1, 0.3)},
    {PT::P_E0, Vec3(0.4, 0, 0), Vec3(0, -1, 0.5)},  {PT::P_E1, Vec3(0.5, 0.5, 0), Vec3(1, 1, 0.4)},
    {PT::P_E2, Vec3(0, 0.6, 0), Vec3(-1, 0, -0.5)},
};

// Edge a from (0,0,0) to (1,0,0); edge b's closest point at the foot on a plus d times a unit
// direction, b running along `along` from `before` of its length behind that point (swapped: b
// reversed).
struct EdgeEdgeContact {
  EE type;
  Vec3 foot, direction, along;
  double before;
  bool swapped;
  Vec12 at(double d) const {
    const Vec3 b0 = foot + d * direction.normalized() - before * along;
    const Vec3 b1 = b0 + along;
    return swapped ? stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), b1, b0) : stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), b0, b1);
  }
};
const std::vector<EdgeEdgeContact> kEdgeEdgeContacts = {
    {EE::EA_EB, Vec3(0.5, 0, 0), Vec3(0, 0, 1), Vec3(0.2, 1, 0), 0.6, false},
    {EE::EA0_EB0, Vec3(0, 0, 0), Vec3(-1, -0.5, 0.5), Vec3(-0.3, -0.5, 0.7), 0.0, false},
    {EE::EA0_EB1, Vec3(0, 0, 0), Vec3(-1, -0.5, 0.5), Vec3(-0.3, -0.5, 0.7), 0.0, true},
    {EE::EA1_EB0, Vec3(1, 0, 0), Vec3(1, -0.5, 0.5), Vec3(0.3, -0.5, 0.7), 0.0, false},
    {EE::EA1_EB1, Vec3(1, 0, 0), Vec3(1, -0.5, 0.5), Vec3(0.3, -0.5, 0.7), 0.0, true},
    {EE::EA_EB0, Vec3(0.5, 0, 0), Vec3(0, 0.6, 0.8), Vec3(0.3, 0.6, 0.8), 0.0, false},
    {EE::EA_EB1, Vec3(0.5, 0, 0), Vec3(0, 0.6, 0.8), Vec3(0.3, 0.6, 0.8), 0.0, true},
    {EE::EA0_EB, Vec3(0, 0, 0), Vec3(-1, 0, 1), Vec3(0, 1, 0), 0.5, false},
    {EE::EA1_EB, Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 1, 0), 0.5, false},
};

// Nearly parallel edges: b of length 0.8 turned by `angle` from a in the xy-plane, at distance d
// above a's middle (line-line type) or beyond a's end a1 (point-point type, EA1_EB0).
Vec12 turned_edges(double angle, double d, bool beyond_end) {
  const Vec3 along = 0.8 * Vec3(std::cos(angle), std::sin(angle), 0.0);
  if (beyond_end) {
    const Vec3 b0 = Vec3(1, 0, 0) + d * Vec3(0.3, 0, 1).normalized();
    return stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), b0, b0 + along);
  }
  const Vec3 middle(0.5, 0.0, d);
  return stencil(Vec3(0, 0, 0), Vec3(1, 0, 0), middle - 0.5 * along, middle + 0.5 * along);
}
// eps_x of the turned edges at rest (parallel): 1e-3 * 1 * 0.64.
const double kThreshold = edge_edge_mollifier_threshold(turned_edges(0.0, 0.1, false));
const EdgeEdgeBarrier kEdgeEdge{3.0, kRange, kThickness, kThreshold};

double point_triangle_gap(const Vec12& x) {
  return std::sqrt(point_triangle_squared_distance(x, point_triangle_distance_type(x))) - kThickness;
}
double edge_edge_gap(const Vec12& x) {
  return std::sqrt(edge_edge_squared_distance(x, edge_edge_distance_type(x))) - kThickness;
}

template <class Kernel>
void expect_zero_beyond_range(const Kernel& kernel, const Vec12& x, const std::string& label) {
  Vec12 g = Vec12::Ones();
  Mat12 H = Mat12::Ones(), P = Mat12::Ones();
  EXPECT_FALSE(kernel.active(x)) << label;
  EXPECT_EQ(kernel.energy(x), 0.0) << label;
  EXPECT_EQ(kernel.gradient(x, g), 0.0) << label;
  EXPECT_TRUE(g.isZero(0.0)) << label;
  kernel.hessian(x, H, false);
  kernel.hessian(x, P, true);
  EXPECT_TRUE(H.isZero(0.0)) << label;
  EXPECT_TRUE(P.isZero(0.0)) << label;
}

TEST(SelfContactKernel, ExactlyZeroAtAndBeyondTheRange) {
  for (double f : {1.0, 1.0 + 1e-9, 1.5, 10.0}) {
    const double d = kThickness + f * kRange;
    for (const auto& c : kPointTriangleContacts) {
      const Vec12 x = c.at(d);
      if (point_triangle_gap(x) < kRange) continue;  // rounding put it inside
      expect_zero_beyond_range(kPointTriangle, x, "PT " + std::to_string(static_cast<int>(c.type)));
    }
    for (const auto& c : kEdgeEdgeContacts) {
      const Vec12 x = c.at(d);
      if (edge_edge_gap(x) < kRange) continue;
      expect_zero_beyond_range(kEdgeEdge, x, "EE " + std::to_string(static_cast<int>(c.type)));
    }
  }
}

// active() (which rules far pairs out by their primitives' boxes first) is the exact test
// gap < dhat, on random pairs scattered over a few ranges: in and out of range, and with boxes
// apart by less than thickness + dhat, by more, and by just about that.
TEST(SelfContactKernel, ActiveIsTheExactRangeTest) {
  std::mt19937 rng(17);
  const double reach = kThickness + kRange;
  std::uniform_real_distribution<double> coordinate(0.0, 0.6 * reach), offset(0.0, 2.5 * reach);
  int in = 0, out = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int split = trial % 2 == 0 ? 1 : 2;  // point-triangle, edge-edge
    std::array<Vec3, 4> p;
    const Vec3 shift(offset(rng), 0.3 * offset(rng), 0.0);
    for (int k = 0; k < 4; ++k) p[k] = Vec3(coordinate(rng), coordinate(rng), coordinate(rng)) + (k < split ? shift : Vec3::Zero());
    const Vec12 x = stencil(p[0], p[1], p[2], p[3]);
    const bool exact = (split == 1 ? point_triangle_gap(x) : edge_edge_gap(x)) < kRange;
    EXPECT_EQ(split == 1 ? kPointTriangle.active(x) : kEdgeEdge.active(x), exact) << trial;
    (exact ? in : out) += 1;
  }
  EXPECT_GT(in, 4000);
  EXPECT_GT(out, 4000);
}

TEST(SelfContactKernel, EnergyGrowsWithoutBoundTowardContact) {
  for (const auto& c : kPointTriangleContacts) {
    double previous = 0.0;
    for (double f : {0.9, 0.5, 1e-2, 1e-4, 1e-8}) {
      const Vec12 x = c.at(kThickness + f * kRange);
      EXPECT_TRUE(kPointTriangle.active(x));
      const double energy = kPointTriangle.energy(x);
      EXPECT_GT(energy, previous) << static_cast<int>(c.type) << " at " << f;
      previous = energy;
    }
    for (double d : {kThickness, 0.5 * kThickness}) {
      if (point_triangle_gap(c.at(d)) > 0.0) continue;  // rounding put it outside
      Vec12 g;
      EXPECT_EQ(kPointTriangle.energy(c.at(d)), std::numeric_limits<double>::infinity());
      EXPECT_EQ(kPointTriangle.gradient(c.at(d), g), std::numeric_limits<double>::infinity());
      EXPECT_TRUE(g.isZero(0.0));
    }
  }
  for (const auto& c : kEdgeEdgeContacts) {
    double previous = 0.0;
    for (double f : {0.9, 0.5, 1e-2, 1e-4, 1e-8}) {
      const double energy = kEdgeEdge.energy(c.at(kThickness + f * kRange));
      EXPECT_GT(energy, previous) << static_cast<int>(c.type) << " at " << f;
      previous = energy;
    }
    EXPECT_EQ(kEdgeEdge.energy(c.at(0.5 * kThickness)), std::numeric_limits<double>::infinity());
  }
  // Exactly parallel edges (m = 0) inside the thickness: still +inf, not 0 * inf.
  EXPECT_EQ(kEdgeEdge.energy(turned_edges(0.0, 0.5 * kThickness, false)), std::numeric_limits<double>::infinity());
}

// Gradient and Hessian against central differences; the projected Hessian positive semi-definite,
// equal to project_psd<12> of the exact one, which has a negative eigenvalue.
template <class Kernel>
void expect_kernel_derivatives(const Kernel& kernel, const Vec12& x, const std::string& label) {
  Vec12 g;
  Mat12 H, P, exact, projected;
  const double value = kernel.gradient(x, g);
  EXPECT_EQ(value, kernel.energy(x)) << label;
  ASSERT_GT(value, 0.0) << label;
  kernel.hessian(x, H, false);
  kernel.hessian(x, P, true);
  const double eps = 1e-7;
  const Vec12 g_fd = testing::central_gradient([&](const Vec12& y) { return kernel.energy(y); }, x, eps);
  const Eigen::MatrixXd H_fd = testing::central_jacobian(
      [&](const Vec12& y) {
        Vec12 gy;
        kernel.gradient(y, gy);
        return Eigen::VectorXd(gy);
      },
      x, eps);
  EXPECT_LT((g - g_fd).norm(), 1e-6 * g.norm()) << label;
  EXPECT_LT((H - H_fd).norm(), 1e-6 * H.norm()) << label;
  EXPECT_LT((H - H.transpose()).norm(), 1e-13 * H.norm()) << label;
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Mat12>(H).eigenvalues().minCoeff(), -1e-8 * H.norm()) << label;
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat12>(P).eigenvalues().minCoeff(), -1e-12 * P.norm()) << label;
  EXPECT_LT((P - project_psd<12>(H)).norm(), 1e-12 * H.norm()) << label;
  kernel.hessian_pair(x, exact, projected);
  EXPECT_EQ(exact, H) << label;
  EXPECT_EQ(projected, P) << label;
}

TEST(SelfContactKernel, PointTriangleDerivativesMatchFiniteDifferences) {
  for (const auto& c : kPointTriangleContacts)
    for (double f : {0.05, 0.3, 0.7, 0.95}) {
      const Vec12 x = c.at(kThickness + f * kRange);
      const std::string label = "PT " + std::to_string(static_cast<int>(c.type)) + " at " + std::to_string(f);
      ASSERT_EQ(point_triangle_distance_type(x), c.type) << label;
      expect_kernel_derivatives(kPointTriangle, x, label);
    }
}

TEST(SelfContactKernel, EdgeEdgeDerivativesMatchFiniteDifferences) {
  for (const auto& c : kEdgeEdgeContacts)
    for (double f : {0.05, 0.3, 0.7, 0.95}) {
      const Vec12 x = c.at(kThickness + f * kRange);
      const std::string label = "EE " + std::to_string(static_cast<int>(c.type)) + " at " + std::to_string(f);
      ASSERT_EQ(edge_edge_distance_type(x), c.type) << label;
      ASSERT_GE(edge_edge_cross_squared_norm(x), kThreshold) << label;  // unmollified
      expect_kernel_derivatives(kEdgeEdge, x, label);
    }
}

TEST(SelfContactKernel, MollifiedEdgeEdgeDerivativesMatchFiniteDifferences) {
  for (bool beyond_end : {false, true})
    for (double angle : {0.004, 0.015, 0.025})
      for (double f : {0.1, 0.5, 0.9}) {
        const Vec12 x = turned_edges(angle, kThickness + f * kRange, beyond_end);
        const std::string label = "angle " + std::to_string(angle) + " at " + std::to_string(f);
        ASSERT_EQ(edge_edge_distance_type(x), beyond_end ? EE::EA1_EB0 : EE::EA_EB) << label;
        const double c = edge_edge_cross_squared_norm(x);
        ASSERT_LT(c, kThreshold) << label;
        // The energy is m b, with b the unmollified barrier's.
        EdgeEdgeBarrier unmollified = kEdgeEdge;
        unmollified.mollifier_threshold = 0.0;
        EXPECT_NEAR(kEdgeEdge.energy(x), edge_edge_mollifier(x, kThreshold) * unmollified.energy(x),
                    1e-15 * unmollified.energy(x));
        Vec12 g;
        Mat12 H, P;
        kEdgeEdge.gradient(x, g);
        kEdgeEdge.hessian(x, H, false);
        kEdgeEdge.hessian(x, P, true);
        const Vec12 g_fd = testing::central_gradient([](const Vec12& y) { return kEdgeEdge.energy(y); }, x, 1e-8);
        const Eigen::MatrixXd H_fd = testing::central_jacobian(
            [](const Vec12& y) {
              Vec12 gy;
              kEdgeEdge.gradient(y, gy);
              return Eigen::VectorXd(gy);
            },
            x, 1e-8);
        EXPECT_LT((g - g_fd).norm(), 1e-6 * g.norm()) << label;
        EXPECT_LT((H - H_fd).norm(), 1e-6 * H.norm()) << label;
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat12>(P).eigenvalues().minCoeff(), -1e-12 * P.norm()) << label;
        EXPECT_LT((P - project_psd<12>(H)).norm(), 1e-12 * H.norm()) << label;
      }
}

// A translation-invariant matrix on `count` of the four vertices: A^T D A with A's rows differences
// of those vertices' coordinates and D random symmetric (positive semi-definite where `psd`).
Mat12 translation_invariant_matrix(const std::array<int, 4>& vertices, int count, bool psd, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix<double, 9, 12> A = Eigen::Matrix<double, 9, 12>::Zero();
  for (int i = 1; i < count; ++i)
    for (int c = 0; c < 3; ++c) {
      A(3 * (i - 1) + c, 3 * vertices[i] + c) = 1.0;
      A(3 * (i - 1) + c, 3 * vertices[0] + c) = -1.0;
    }
  Eigen::Matrix<double, 9, 9> B;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) B(i, j) = normal(rng);
  const Eigen::Matrix<double, 9, 9> D = psd ? Eigen::Matrix<double, 9, 9>(B * B.transpose()) : B + B.transpose();
  return A.transpose() * D * A;
}

TEST(SelfContactKernel, TranslationInvariantProjectionEqualsTheFullOne) {
  std::mt19937 rng(21);
  const std::vector<std::pair<std::array<int, 4>, int>> supports = {
      {{0, 2, 0, 0}, 2}, {{1, 2, 3, 0}, 3}, {{0, 1, 3, 0}, 3}, {{0, 1, 2, 3}, 4}};
  for (const auto& [vertices, count] : supports) {
    const Mat12 psd = translation_invariant_matrix(vertices, count, true, rng);
    Mat12 unchanged = psd;
    project_translation_invariant_psd(unchanged, vertices, count);
    EXPECT_EQ(unchanged, psd) << count;
    const Mat12 indefinite = translation_invariant_matrix(vertices, count, false, rng);
    ASSERT_LT(Eigen::SelfAdjointEigenSolver<Mat12>(indefinite).eigenvalues().minCoeff(), 0.0);
    Mat12 projected = indefinite;
    project_translation_invariant_psd(projected, vertices, count);
    EXPECT_LT((projected - project_psd<12>(indefinite)).norm(), 1e-12 * indefinite.norm()) << count;
  }
}

TEST(SelfContactKernel, InvariantUnderRigidMotions) {
  std::mt19937 rng(22);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 3; ++trial) {
    const Mat3 R =
        Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
    const Vec3 t(normal(rng), normal(rng), normal(rng));
    auto move = [&](const Vec12& x) {
      Vec12 y;
      for (int k = 0; k < 4; ++k) y.segment<3>(3 * k) = R * x.segment<3>(3 * k) + t;
      return y;
    };
    auto check = [&](const auto& kernel, const Vec12& x) {
      Vec12 g, g_moved;
      const double e = kernel.gradient(x, g);
      EXPECT_NEAR(kernel.gradient(move(x), g_moved), e, 1e-12 * e);
      for (int k = 0; k < 4; ++k)
        EXPECT_LT((g_moved.segment<3>(3 * k) - R * g.segment<3>(3 * k)).norm(), 1e-10 * g.norm());
    };
    for (const auto& c : kPointTriangleContacts) check(kPointTriangle, c.at(kThickness + 0.4 * kRange));
    for (const auto& c : kEdgeEdgeContacts) check(kEdgeEdge, c.at(kThickness + 0.4 * kRange));
    check(kEdgeEdge, turned_edges(0.01, kThickness + 0.4 * kRange, false));
  }
}

void expect_valid_frame(const ContactTangentFrame& frame, const Vec12& x, double squared_distance,
                        const std::string& label) {
  const Eigen::Matrix<double, 3, 2>& T = frame.basis;
  EXPECT_LT((T.transpose() * T - Eigen::Matrix2d::Identity()).norm(), 1e-14) << label;
  EXPECT_LT((T.transpose() * frame.normal).norm(), 1e-14) << label;
  EXPECT_NEAR(frame.normal.norm(), 1.0, 1e-15) << label;
  EXPECT_NEAR(frame.weights.sum(), 0.0, 1e-15) << label;
  // The weights give the closest points' difference, along the normal.
  Vec3 difference = Vec3::Zero();
  for (int k = 0; k < 4; ++k) difference += frame.weights[k] * x.segment<3>(3 * k);
  EXPECT_NEAR(difference.dot(frame.normal), std::sqrt(squared_distance), 1e-14) << label;
  // A common translation slips nothing; moving the first primitive along a tangent slips by that.
  const Vec3 shift(0.3, -0.2, 0.5);
  Vec12 moved = x, slid = x;
  for (int k = 0; k < 4; ++k) moved.segment<3>(3 * k) += shift;
  const Vec3 tangent = 0.01 * T.col(0) - 0.02 * T.col(1);
  for (int k = 0; k < 4; ++k)
    if (frame.weights[k] > 0.0) slid.segment<3>(3 * k) += tangent;
  EXPECT_LT(frame.tangent_displacement(moved, x).norm(), 1e-15) << label;
  EXPECT_LT((frame.tangent_displacement(slid, x) - Eigen::Vector2d(0.01, -0.02)).norm(), 1e-15) << label;
  EXPECT_LT((frame.displacement_jacobian() * (slid - x) - frame.tangent_displacement(slid, x)).norm(), 1e-15) << label;
}

TEST(SelfContactKernel, FrictionFramesOfPointTrianglePairs) {
  for (const auto& c : kPointTriangleContacts) {
    const Vec12 x = c.at(kThickness + 0.5 * kRange);
    const ContactTangentFrame frame = point_triangle_tangent_frame(x);
    expect_valid_frame(frame, x, point_triangle_squared_distance(x, c.type),
                       "PT " + std::to_string(static_cast<int>(c.type)));
    EXPECT_NEAR(std::abs(frame.normal.dot(c.direction.normalized())), 1.0, 1e-14);
    EXPECT_EQ(frame.weights[0], 1.0);
  }
}

TEST(SelfContactKernel, FrictionFramesOfEdgeEdgePairs) {
  for (const auto& c : kEdgeEdgeContacts) {
    const Vec12 x = c.at(kThickness + 0.5 * kRange);
    const ContactTangentFrame frame = edge_edge_tangent_frame(x);
    expect_valid_frame(frame, x, edge_edge_squared_distance(x, c.type),
                       "EE " + std::to_string(static_cast<int>(c.type)));
    EXPECT_NEAR(std::abs(frame.normal.dot(c.direction.normalized())), 1.0, 1e-14);
  }
  // Line-line: the normal is ea x eb's direction, the tangent plane that of both edges.
  const Vec12 x = kEdgeEdgeContacts[0].at(0.05);
  const ContactTangentFrame frame = edge_edge_tangent_frame(x);
  const Vec3 cross = (x.segment<3>(3) - x.segment<3>(0)).cross(x.segment<3>(9) - x.segment<3>(6)).normalized();
  EXPECT_NEAR(std::abs(frame.normal.dot(cross)), 1.0, 1e-15);
}

TEST(SelfContactKernel, FrictionFrameWhereTheClosestPointsCoincide) {
  // A point on the triangle: the triangle's normal.
  const Vec12 x = kPointTriangleContacts[0].at(0.0);
  const ContactTangentFrame frame = point_triangle_tangent_frame(x);
  EXPECT_NEAR(std::abs(frame.normal.z()), 1.0, 1e-15);
  EXPECT_LT((frame.basis.transpose() * frame.basis - Eigen::Matrix2d::Identity()).norm(), 1e-14);
}

}  // namespace
}  // namespace fnopt
