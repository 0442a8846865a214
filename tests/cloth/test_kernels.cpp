// Finite-difference checks of every per-stencil kernel (gradient and Hessian), zero energy and
// gradient at rest, invariance under rigid motions, and the PSD projection.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include <fnopt/cloth/angle_kernel.hpp>
#include <fnopt/cloth/stretch_kernel.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

constexpr double kH = 0.1;

template <class Kernel>
typename Kernel::Vec perturbed(const typename Kernel::Vec& rest, double amplitude, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, amplitude);
  typename Kernel::Vec x = rest;
  for (int i = 0; i < x.size(); ++i) x[i] += normal(rng);
  return x;
}

// Central differences of the energy against the analytic gradient, and of the analytic
// gradient against the analytic (unprojected) Hessian.
template <class Kernel>
void check_derivatives(const Kernel& kernel, const typename Kernel::Vec& x) {
  using Vec = typename Kernel::Vec;
  using Mat = typename Kernel::Mat;
  Vec g;
  kernel.gradient(x, g);
  Mat H;
  kernel.hessian(x, H, false);
  ASSERT_GT(g.norm(), 1e-8) << "test state must be deformed";
  const double eps = 1e-6;
  const Vec g_fd = testing::central_gradient([&](const Vec& y) { return kernel.energy(y); }, x, eps);
  const Mat H_fd = testing::central_jacobian(
      [&](const Vec& y) {
        Vec gy;
        kernel.gradient(y, gy);
        return Eigen::VectorXd(gy);
      },
      x, eps);
  EXPECT_LT((g - g_fd).norm(), 1e-6 * g.norm()) << "gradient\n" << g.transpose() << "\n" << g_fd.transpose();
  EXPECT_LT((H - H_fd).norm(), 1e-5 * H.norm()) << "hessian";
  EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
}

StretchKernel stretch() { return {30.0, kH}; }
AngleKernel shear() { return AngleKernel::shear(3.0, kH); }
AngleKernel bend() { return AngleKernel::bend(2e-5); }

StretchKernel::Vec stretch_rest() {
  StretchKernel::Vec x;
  x << 0, 0, 0, kH, 0, 0;
  return x;
}
AngleKernel::Vec corner_rest() {  // corner at origin, neighbours along +x and -z
  AngleKernel::Vec x;
  x << 0, 0, 0, kH, 0, 0, 0, 0, -kH;
  return x;
}
AngleKernel::Vec hinge_rest() {
  AngleKernel::Vec x;
  x << 0, 0, 0, kH, 0, 0, 2 * kH, 0, 0;
  return x;
}

TEST(StretchKernel, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 20; ++trial)
    check_derivatives(stretch(), perturbed<StretchKernel>(stretch_rest(), 0.3 * kH, rng));
}

TEST(ShearKernel, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 20; ++trial)
    check_derivatives(shear(), perturbed<AngleKernel>(corner_rest(), 0.3 * kH, rng));
}

TEST(BendKernel, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial)
    check_derivatives(bend(), perturbed<AngleKernel>(hinge_rest(), 0.3 * kH, rng));
}

TEST(BendKernel, DerivativesNearFlatUseTheSeriesConsistently) {
  // Bend angles around 1e-4 and 1e-3 exercise both sides of the series switch.
  std::mt19937 rng(4);
  for (double amplitude : {2e-5 * kH, 2e-4 * kH, 2e-3 * kH}) {
    AngleKernel::Vec x = perturbed<AngleKernel>(hinge_rest(), amplitude, rng);
    AngleKernel::Vec g;
    bend().gradient(x, g);
    AngleKernel::Mat H;
    bend().hessian(x, H, false);
    const AngleKernel::Mat H_fd = testing::central_jacobian(
        [](const AngleKernel::Vec& y) {
          AngleKernel::Vec gy;
          bend().gradient(y, gy);
          return Eigen::VectorXd(gy);
        },
        x, 1e-7 * kH);
    EXPECT_LT((H - H_fd).norm(), 1e-5 * H.norm()) << "amplitude " << amplitude;
  }
}

template <class Kernel>
void check_rest(const Kernel& kernel, const typename Kernel::Vec& rest) {
  typename Kernel::Vec g;
  EXPECT_NEAR(kernel.gradient(rest, g), 0.0, 1e-20);
  EXPECT_LT(g.norm(), 1e-15);
}

TEST(Kernels, ZeroEnergyAndGradientAtRest) {
  check_rest(stretch(), stretch_rest());
  check_rest(shear(), corner_rest());
  check_rest(bend(), hinge_rest());
}

template <class Kernel>
void check_rigid_invariance(const Kernel& kernel, const typename Kernel::Vec& rest, int seed) {
  std::mt19937 rng(seed);
  const typename Kernel::Vec x = perturbed<Kernel>(rest, 0.3 * kH, rng);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -1.2, 2.0);
  typename Kernel::Vec y;
  for (int i = 0; i < Kernel::kVertices; ++i) y.template segment<3>(3 * i) = R * x.template segment<3>(3 * i) + t;
  EXPECT_NEAR(kernel.energy(y), kernel.energy(x), 1e-12 * kernel.energy(x));
  typename Kernel::Vec gx, gy;
  kernel.gradient(x, gx);
  kernel.gradient(y, gy);
  for (int i = 0; i < Kernel::kVertices; ++i)  // the gradient rotates with the stencil
    EXPECT_LT((gy.template segment<3>(3 * i) - R * gx.template segment<3>(3 * i)).norm(), 1e-10 * gx.norm());
  // Translation invariance: the gradient's per-vertex sum (net force) vanishes.
  Eigen::Vector3d net = Eigen::Vector3d::Zero();
  for (int i = 0; i < Kernel::kVertices; ++i) net += gx.template segment<3>(3 * i);
  EXPECT_LT(net.norm(), 1e-12 * gx.norm());
}

TEST(Kernels, InvariantUnderRigidMotions) {
  check_rigid_invariance(stretch(), stretch_rest(), 5);
  check_rigid_invariance(shear(), corner_rest(), 6);
  check_rigid_invariance(bend(), hinge_rest(), 7);
}

template <class Kernel>
void check_projection(const Kernel& kernel, const typename Kernel::Vec& rest, int seed) {
  std::mt19937 rng(seed);
  int indefinite = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const typename Kernel::Vec x = perturbed<Kernel>(rest, 0.4 * kH, rng);
    typename Kernel::Mat H, P;
    kernel.hessian(x, H, false);
    kernel.hessian(x, P, true);
    Eigen::SelfAdjointEigenSolver<typename Kernel::Mat> exact(H), projected(P);
    indefinite += exact.eigenvalues().minCoeff() < -1e-12 * H.norm();
    EXPECT_GE(projected.eigenvalues().minCoeff(), -1e-10 * H.norm());
  }
  EXPECT_GT(indefinite, 0) << "the sample must contain indefinite stencils to test anything";
}

TEST(Kernels, ProjectedHessiansArePositiveSemidefinite) {
  check_projection(stretch(), stretch_rest(), 8);
  check_projection(shear(), corner_rest(), 9);
  check_projection(bend(), hinge_rest(), 10);
}

// hessian_pair (the Newton reference's rebuilds of P) gives hessian(x, false) and hessian(x, true),
// the same bits, from one evaluation; compressed edges and stencils far from rest included.
template <class Kernel>
void check_pair(const Kernel& kernel, const typename Kernel::Vec& rest, unsigned seed) {
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 50; ++trial) {
    const typename Kernel::Vec x = perturbed<Kernel>(rest, 0.4 * kH, rng);
    typename Kernel::Mat exact, projected, pair_exact, pair_projected;
    kernel.hessian(x, exact, false);
    kernel.hessian(x, projected, true);
    kernel.hessian_pair(x, pair_exact, pair_projected);
    EXPECT_TRUE(pair_exact == exact) << "trial " << trial;
    EXPECT_TRUE(pair_projected == projected) << "trial " << trial;
  }
}

TEST(Kernels, TheHessianPairIsTheTwoHessians) {
  check_pair(stretch(), stretch_rest(), 21);
  check_pair(shear(), corner_rest(), 22);
  check_pair(bend(), hinge_rest(), 23);
}

// shear() and bend() map the 6x6 Hessian in (u, w) to the vertices by sums of its blocks; the general
// map's products with their coefficients give the same values.
TEST(AngleKernel, TheCornerAndHingeLayoutsAreTheGeneralMap) {
  std::mt19937 rng(31);
  for (const auto& [kernel, rest] : {std::pair{shear(), corner_rest()}, std::pair{bend(), hinge_rest()}}) {
    ASSERT_NE(kernel.layout, AngleKernel::Layout::General);
    AngleKernel general = kernel;
    general.layout = AngleKernel::Layout::General;
    for (int trial = 0; trial < 50; ++trial) {
      const AngleKernel::Vec x = perturbed<AngleKernel>(rest, 0.4 * kH, rng);
      for (const bool project : {false, true}) {
        AngleKernel::Mat laid_out, mapped;
        kernel.hessian(x, laid_out, project);
        general.hessian(x, mapped, project);
        EXPECT_TRUE(laid_out == mapped) << "trial " << trial << (project ? ", projected" : "");
      }
    }
  }
}

TEST(PsdProjection, FlipsOnlyNegativeEigenvalues) {
  Eigen::Matrix3d Q = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Eigen::Matrix3d H = Q * Eigen::Vector3d(2.0, -1.0, 0.5).asDiagonal() * Q.transpose();
  const Eigen::Matrix3d expected = Q * Eigen::Vector3d(2.0, 1.0, 0.5).asDiagonal() * Q.transpose();
  EXPECT_LT((project_psd<3>(H) - expected).norm(), 1e-12);
  const Eigen::Matrix3d spd = Q * Eigen::Vector3d(2.0, 1.0, 0.5).asDiagonal() * Q.transpose();
  EXPECT_EQ(project_psd<3>(spd), spd);
}

}  // namespace
}  // namespace fnopt
