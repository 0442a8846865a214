// The batched angle kernels (cloth/angle_batch.hpp) against the scalar AngleKernel, stencil by
// stencil, on every instruction set this CPU has, for both layouts (Corner = shear, Hinge = bend):
// random deformations, near-flat hinges (theta < 1e-3, the series), angles near pi, and exactly
// collinear stencils. The two differ only in atan2's last bit, which is relative to theta; where
// theta - theta0 cancels (a shear corner near its right angle) the gradient's error is relative to
// the gradient a spring of rest angle 0 would have on the same stencil. So the bound, per stencil:
//   |g_batch - g_scalar| <= 1e-13 (|g_scalar| + |g_scalar at theta0 = 0|),
// and the same for the energy and (with the Frobenius norm) the unprojected Hessian.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <fnopt/cloth/angle_batch.hpp>
#include <fnopt/cloth/angle_kernel.hpp>

namespace fnopt {
namespace {

constexpr double kH = 0.1;
constexpr double kTolerance = 1e-13;

AngleKernel shear() { return AngleKernel::shear(3.0, kH); }
AngleKernel bend() { return AngleKernel::bend(2e-5); }

// Stencils with their own vertices: stencil s's vertex i is vertex 3s + i of x.
struct Stencils {
  std::vector<AngleKernel::Vec> local;
  std::vector<double> x;
  void add(const AngleKernel::Vec& stencil) {
    local.push_back(stencil);
    x.insert(x.end(), stencil.data(), stencil.data() + 9);
  }
};

AngleKernel::Vec points(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  AngleKernel::Vec x;
  x << a, b, c;
  return x;
}

// Stencil shapes: x0, x1, x2 for the given layout whose angle is theta (between u and w).
AngleKernel::Vec with_angle(const AngleKernel& kernel, double theta, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d u = kH * Eigen::Vector3d(1, 0, 0);
  const Eigen::Vector3d w = 1.3 * kH * (std::cos(theta) * Eigen::Vector3d(1, 0, 0) + std::sin(theta) * axis);
  const Eigen::Vector3d origin(0.2, -0.4, 0.7);
  if (kernel.layout == AngleKernel::Layout::Corner) return points(origin, origin + u, origin + w);
  return points(origin, origin + u, origin + u + w);
}

Stencils test_stencils(const AngleKernel& kernel, int seed) {
  Stencils stencils;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto random_axis = [&] { return Eigen::Vector3d(0, normal(rng), normal(rng)).normalized(); };
  auto jitter = [&](AngleKernel::Vec x, double amplitude) {
    for (int i = 0; i < 9; ++i) x[i] += amplitude * normal(rng);
    return x;
  };
  const double rest = kernel.rest_angle;
  for (int k = 0; k < 68; ++k) stencils.add(jitter(with_angle(kernel, rest, random_axis()), 0.3 * kH));
  for (int k = 0; k < 32; ++k)  // a rest angle's neighbourhood: for bend the series, on both sides of 1e-3
    stencils.add(with_angle(kernel, rest + std::pow(10.0, -7.0 + 5.0 * uniform(rng)), random_axis()));
  for (int k = 0; k < 16; ++k) stencils.add(with_angle(kernel, rest - 1e-9 * uniform(rng), random_axis()));
  for (int k = 0; k < 16; ++k)  // near pi and near 0
    stencils.add(with_angle(kernel, M_PI - std::pow(10.0, -7.0 + 6.0 * uniform(rng)), random_axis()));
  for (int k = 0; k < 16; ++k)
    stencils.add(with_angle(kernel, std::pow(10.0, -7.0 + 6.0 * uniform(rng)), random_axis()));
  // Exactly collinear: theta = 0 and pi with sin = 0.
  const Eigen::Vector3d a(0, 0, 0), b(kH, 0, 0), c(2 * kH, 0, 0), d(-kH, 0, 0);
  const bool corner = kernel.layout == AngleKernel::Layout::Corner;
  for (const AngleKernel::Vec& x :
       corner ? std::vector{points(a, b, c), points(a, b, d), points(b, a, c), points(a, c, b)}
              : std::vector{points(a, b, c), points(a, b, a), points(c, b, a), points(b, a, b)})
    stencils.add(x);
  return stencils;
}

// Coordinate offsets of batches of `width` consecutive stencils (angle_batch.hpp's layout).
std::vector<int> batch_offsets(long count, int width) {
  std::vector<int> offsets(3 * count);
  for (long b = 0; b < count / width; ++b)
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < width; ++l) offsets[(3 * b + i) * width + l] = 3 * (3 * (b * width + l) + i);
  return offsets;
}

AngleKernel at_rest_angle_zero(AngleKernel kernel) {
  kernel.rest_angle = 0.0;
  return kernel;
}

void check_gradients(const AngleKernel& kernel, SimdLevel level, int seed) {
  if (!simd_level_supported(level)) GTEST_SKIP() << "this CPU has no " << simd_level_name(level);
  const AngleBatchKernels batch = angle_batch_kernels(level);
  const Stencils stencils = test_stencils(kernel, seed);
  const int width = batch.width;
  const long batches = static_cast<long>(stencils.local.size()) / width;
  ASSERT_EQ(static_cast<long>(stencils.local.size()), batches * width);
  const std::vector<int> offsets = batch_offsets(batches * width, width);
  const AngleBatchParams params{kernel.stiffness, kernel.rest_angle, kernel.layout == AngleKernel::Layout::Corner};
  std::vector<double> out(10 * width * batches), energies(width * batches), hessians(81 * width * batches);
  batch.gradients(params, stencils.x.data(), offsets.data(), batches, out.data());
  batch.energies(params, stencils.x.data(), offsets.data(), batches, energies.data());
  batch.hessians(params, stencils.x.data(), offsets.data(), batches, hessians.data());
  int identical = 0;
  for (long s = 0; s < batches * width; ++s) {
    const double* lanes = out.data() + 10 * width * (s / width) + s % width;
    AngleKernel::Vec g, g_scale, g_batch;
    const double energy = kernel.gradient(stencils.local[s], g);
    const double energy_scale = at_rest_angle_zero(kernel).gradient(stencils.local[s], g_scale);
    for (int k = 0; k < 9; ++k) g_batch[k] = lanes[k * width];
    const double scale = g.norm() + g_scale.norm();
    EXPECT_LE((g_batch - g).norm(), kTolerance * scale) << "stencil " << s << "\n"
                                                        << g.transpose() << "\n"
                                                        << g_batch.transpose();
    EXPECT_LE(std::fabs(lanes[9 * width] - energy), kTolerance * (energy + energy_scale)) << "stencil " << s;
    EXPECT_LE(std::fabs(energies[s] - kernel.energy(stencils.local[s])), kTolerance * (energy + energy_scale))
        << "stencil " << s;
    identical += g_batch == g;
    AngleKernel::Mat H, H_scale, H_batch;
    kernel.hessian(stencils.local[s], H, false);
    at_rest_angle_zero(kernel).hessian(stencils.local[s], H_scale, false);
    for (int k = 0; k < 81; ++k) H_batch.data()[k] = hessians[81 * width * (s / width) + k * width + s % width];
    EXPECT_LE((H_batch - H).norm(), kTolerance * (H.norm() + H_scale.norm())) << "stencil " << s;
  }
  // Most stencils' atan2 is the same double, and then every coordinate is.
  EXPECT_GT(identical, batches * width / 2);
}

// The two sets run the same operations per lane, so their results are the same doubles: a rollout
// does not depend on which of them the CPU has.
TEST(AngleBatch, Avx2AndAvx512GiveTheSameBits) {
  if (!simd_level_supported(SimdLevel::Avx512) || !simd_level_supported(SimdLevel::Avx2))
    GTEST_SKIP() << "this CPU lacks AVX2 or AVX-512";
  for (const AngleKernel& kernel : {shear(), bend()}) {
    const Stencils stencils = test_stencils(kernel, 5);
    const long count = static_cast<long>(stencils.local.size());
    const AngleBatchParams params{kernel.stiffness, kernel.rest_angle, kernel.layout == AngleKernel::Layout::Corner};
    std::vector<double> gradients[2], energies[2], hessians[2];
    int k = 0;
    for (SimdLevel level : {SimdLevel::Avx2, SimdLevel::Avx512}) {
      const AngleBatchKernels batch = angle_batch_kernels(level);
      const std::vector<int> offsets = batch_offsets(count, batch.width);
      const long batches = count / batch.width;
      std::vector<double> out(10 * batch.width * batches), hessian(81 * batch.width * batches);
      energies[k].resize(count);
      batch.gradients(params, stencils.x.data(), offsets.data(), batches, out.data());
      batch.energies(params, stencils.x.data(), offsets.data(), batches, energies[k].data());
      batch.hessians(params, stencils.x.data(), offsets.data(), batches, hessian.data());
      for (long s = 0; s < count; ++s) {  // stencil by stencil: 10 values, then 81
        for (int row = 0; row < 10; ++row)
          gradients[k].push_back(out[10 * batch.width * (s / batch.width) + row * batch.width + s % batch.width]);
        for (int row = 0; row < 81; ++row)
          hessians[k].push_back(hessian[81 * batch.width * (s / batch.width) + row * batch.width + s % batch.width]);
      }
      ++k;
    }
    EXPECT_EQ(gradients[0], gradients[1]);
    EXPECT_EQ(energies[0], energies[1]);
    EXPECT_EQ(hessians[0], hessians[1]);
  }
}

TEST(AngleBatch, ShearAvx2MatchesScalarKernel) { check_gradients(shear(), SimdLevel::Avx2, 1); }
TEST(AngleBatch, ShearAvx512MatchesScalarKernel) { check_gradients(shear(), SimdLevel::Avx512, 2); }
TEST(AngleBatch, BendAvx2MatchesScalarKernel) { check_gradients(bend(), SimdLevel::Avx2, 3); }
TEST(AngleBatch, BendAvx512MatchesScalarKernel) { check_gradients(bend(), SimdLevel::Avx512, 4); }

}  // namespace
}  // namespace fnopt
