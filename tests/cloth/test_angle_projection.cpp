// The angle spring's closed-form projection against the numerical one (project_psd<6>, an Eigen
// eigen-decomposition) on the exact Hessian in (u, w): bending and shear, near flat, near folded,
// stretched and compressed edges, and the degenerate corners where it hands back to the caller.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include <fnopt/cloth/angle_kernel.hpp>
#include <fnopt/cloth/angle_projection.hpp>
#include <fnopt/cloth/psd_projection.hpp>

namespace fnopt {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
constexpr double kHalfPi = 1.5707963267948966;

double angle(const Eigen::Vector3d& u, const Eigen::Vector3d& w) { return std::atan2(u.cross(w).norm(), u.dot(w)); }

// The exact Hessian in (u, w), read from the kernel's 9x9 one on the hinge x = (0, u, u + w), where
// u = x1 - x0 and w = x2 - x1: d2E/dx0^2 = Huu, d2E/dx2^2 = Hww, d2E/dx0 dx2 = -Huw.
Mat6 hessian_in_edges(double stiffness, double rest_angle, const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
  const AngleKernel kernel{stiffness, rest_angle, {-1, 1, 0}, {0, -1, 1}};
  AngleKernel::Vec x;
  x << Eigen::Vector3d::Zero(), u, u + w;
  AngleKernel::Mat H;
  kernel.hessian(x, H, false);
  Mat6 Huw;
  Huw << H.block<3, 3>(0, 0), -H.block<3, 3>(0, 6), -H.block<3, 3>(6, 0), H.block<3, 3>(6, 6);
  return Huw;
}

// Closed form against numerical on one configuration; returns the relative difference.
double closed_form_error(double stiffness, double rest_angle, const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
  const Mat6 exact = hessian_in_edges(stiffness, rest_angle, u, w);
  Mat6 closed = exact;
  EXPECT_TRUE(project_angle_hessian(u, w, stiffness, angle(u, w) - rest_angle, closed));
  return (closed - project_psd<6>(exact)).norm() / exact.norm();
}

Eigen::Vector3d random_vector(std::mt19937& rng, double scale) {
  std::normal_distribution<double> normal(0.0, scale);
  return {normal(rng), normal(rng), normal(rng)};
}

TEST(AngleProjection, EqualsTheNumericalProjectionOnRandomEdges) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.2, 3.0);
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3d u = random_vector(rng, 1.0), w = random_vector(rng, 1.0);
    worst = std::max(worst, closed_form_error(uniform(rng), trial % 2 ? 0.0 : kHalfPi, u, w));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(AngleProjection, EqualsTheNumericalProjectionOnCloseToRestHinges) {
  // A grid's hinges and corners: edges of nearly equal length, nearly flat (bend) or nearly square
  // (shear), one edge stretched or compressed by up to 50 %.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> stretch(0.5, 1.5);
  double worst = 0.0;
  for (const double tilt : {1e-8, 1e-5, 1e-3, 0.05, 0.3}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d u = 0.1 * Eigen::Vector3d::UnitX() + random_vector(rng, 0.1 * tilt);
      const Eigen::Vector3d bend_w = stretch(rng) * 0.1 * Eigen::Vector3d::UnitX() + random_vector(rng, 0.1 * tilt);
      const Eigen::Vector3d shear_w = stretch(rng) * 0.1 * Eigen::Vector3d::UnitY() + random_vector(rng, 0.1 * tilt);
      worst = std::max(worst, closed_form_error(2e-4, 0.0, u, bend_w));
      worst = std::max(worst, closed_form_error(50.0, kHalfPi, u, shear_w));
    }
  }
  EXPECT_LT(worst, 1e-11);
}

TEST(AngleProjection, EqualsTheNumericalProjectionNearlyFolded) {
  std::mt19937 rng(5);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d u = Eigen::Vector3d::UnitX() + random_vector(rng, 0.05);
    const Eigen::Vector3d w = -0.8 * Eigen::Vector3d::UnitX() + random_vector(rng, 0.05);  // theta near pi
    worst = std::max(worst, closed_form_error(1.0, 0.0, u, w));
    worst = std::max(worst, closed_form_error(1.0, kHalfPi, u, w));
  }
  EXPECT_LT(worst, 1e-11);
}

TEST(AngleProjection, ResultIsPositiveSemidefiniteWithTheExactPositiveEigenvalues) {
  std::mt19937 rng(6);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d u = random_vector(rng, 1.0), w = random_vector(rng, 1.0);
    const Mat6 exact = hessian_in_edges(1.0, kHalfPi, u, w);
    Mat6 projected = exact;
    ASSERT_TRUE(project_angle_hessian(u, w, 1.0, angle(u, w) - kHalfPi, projected));
    Eigen::SelfAdjointEigenSolver<Mat6> before(exact), after(projected);
    Eigen::Matrix<double, 6, 1> expected = before.eigenvalues().cwiseAbs();
    std::sort(expected.data(), expected.data() + 6);
    EXPECT_LT((after.eigenvalues() - expected).norm(), 1e-12 * exact.norm());
    EXPECT_EQ((before.eigenvalues().array() < -1e-12 * exact.norm()).count(), 3)
        << "an angle spring's Hessian off its rest angle has three negative eigenvalues";
  }
}

TEST(AngleProjection, LeavesDegenerateCornersToTheCaller) {
  const Eigen::Vector3d u = Eigen::Vector3d::UnitX(), w = 2.0 * Eigen::Vector3d::UnitX();
  // A flat hinge at rest: nothing to flip.
  Mat6 flat = hessian_in_edges(1.0, 0.0, u, w);
  const Mat6 before = flat;
  EXPECT_TRUE(project_angle_hessian(u, w, 1.0, 0.0, flat));
  EXPECT_EQ(flat, before);
  // A shear corner collapsed onto a line (theta = 0, delta = -pi/2): no plane to work in.
  Mat6 collapsed = hessian_in_edges(1.0, kHalfPi, u, w);
  const Mat6 kept = collapsed;
  EXPECT_FALSE(project_angle_hessian(u, w, 1.0, -kHalfPi, collapsed));
  EXPECT_EQ(collapsed, kept);
}

TEST(AngleProjection, TheKernelsProjectedHessianUsesIt) {
  // AngleKernel::hessian(project = true) equals the numerical projection of its exact Hessian, mapped
  // to the vertices.
  const AngleKernel kernel = AngleKernel::shear(30.0, 0.1);
  AngleKernel::Vec x;
  x << 0.0, 0.0, 0.0, 0.1, 0.01, 0.02, -0.01, 0.12, -0.03;
  AngleKernel::Mat H, P;
  kernel.hessian(x, H, false);
  kernel.hessian(x, P, true);
  Eigen::SelfAdjointEigenSolver<AngleKernel::Mat> exact(H), projected(P);
  EXPECT_LT(exact.eigenvalues().minCoeff(), -1e-6 * H.norm());
  EXPECT_GE(projected.eigenvalues().minCoeff(), -1e-12 * H.norm());
  // The shear kernel's edges are u = x1 - x0, w = x2 - x0: H = C^T Huw C with C = [[-I, I, 0], [-I, 0, I]].
  Mat6 Huw;
  Huw << H.block<3, 3>(3, 3), H.block<3, 3>(3, 6), H.block<3, 3>(6, 3), H.block<3, 3>(6, 6);
  const Mat6 expected = project_psd<6>(Huw);
  Mat6 got;
  got << P.block<3, 3>(3, 3), P.block<3, 3>(3, 6), P.block<3, 3>(6, 3), P.block<3, 3>(6, 6);
  EXPECT_LT((got - expected).norm(), 1e-12 * Huw.norm());
}

}  // namespace
}  // namespace fnopt
