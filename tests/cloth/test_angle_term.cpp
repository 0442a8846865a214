// The batched angle term (cloth/angle_term.hpp) against the scalar StencilTerm<AngleKernel> on a
// whole grid cloth, shear and bend, at every level this CPU has: energy, assembled gradient and
// unprojected Hessian to 1e-13 relative, on one thread and on two (the parallel path), with stencil
// counts that leave a partial last batch; the projected Hessian is the scalar term's; its
// derivatives match central differences.
#include <gtest/gtest.h>

#include <omp.h>

#include <Eigen/SparseCore>
#include <random>
#include <vector>

#include <fnopt/cloth/angle_term.hpp>
#include <fnopt/cloth/cloth_terms.hpp>
#include <fnopt/cloth/grid.hpp>
#include "tests/util/energy_term_derivatives.hpp"

namespace fnopt {
namespace {

struct DeformedCloth {
  Grid grid;
  VecX x;
};

// A rows x cols cloth with every vertex moved by a normal of standard deviation `amplitude` cells.
DeformedCloth deformed_cloth(int rows, int cols, double amplitude, int seed) {
  DeformedCloth s{Grid::make(rows, cols, 1.0), {}};
  s.x = s.grid.rest_positions();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, amplitude * s.grid.spacing);
  for (Eigen::Index i = 0; i < s.x.size(); ++i) s.x[i] += normal(rng);
  return s;
}

AngleTerm shear_term(const Grid& grid, SimdLevel level) {
  return AngleTerm("shear", AngleKernel::shear(3.0, grid.spacing), grid_shear_corners(grid), level);
}
AngleTerm bend_term(const Grid& grid, SimdLevel level) {
  return AngleTerm("bend", AngleKernel::bend(2e-5), grid_bend_hinges(grid), level);
}

void expect_same_as_scalar(const AngleTerm& batched, const AngleTerm& scalar, const VecX& x) {
  VecX g = VecX::Zero(x.size()), g_scalar = VecX::Zero(x.size());
  const double e = batched.accumulate_gradient(x, g), e_scalar = scalar.accumulate_gradient(x, g_scalar);
  EXPECT_LE(std::abs(e - e_scalar), 1e-13 * e_scalar);
  EXPECT_LE((g - g_scalar).norm(), 1e-13 * g_scalar.norm());
  EXPECT_LE(std::abs(batched.energy(x) - scalar.energy(x)), 1e-13 * e_scalar);
  const Eigen::SparseMatrix<double> H = testing::assembled_hessian(batched, x, false),
                                    H_scalar = testing::assembled_hessian(scalar, x, false);
  EXPECT_LE((H - H_scalar).norm(), 1e-13 * H_scalar.norm());
  // The projected Hessian is the scalar term's.
  EXPECT_EQ((testing::assembled_hessian(batched, x, true) - testing::assembled_hessian(scalar, x, true)).norm(), 0.0);
}

void check_level(SimdLevel level) {
  if (!simd_level_supported(level)) GTEST_SKIP() << "this CPU has no " << simd_level_name(level);
  // 13 x 11: 480 corners and 238 hinges, neither a multiple of 8 nor 4 (a partial last batch).
  // 37 x 41: over StencilTerm's parallel threshold, run on one thread and on two.
  for (const auto& [rows, cols] : {std::pair{13, 11}, std::pair{37, 41}}) {
    const DeformedCloth s = deformed_cloth(rows, cols, 0.2, rows);
    for (bool shear : {true, false}) {
      const AngleTerm batched = shear ? shear_term(s.grid, level) : bend_term(s.grid, level);
      const AngleTerm scalar = shear ? shear_term(s.grid, SimdLevel::Scalar) : bend_term(s.grid, SimdLevel::Scalar);
      EXPECT_EQ(batched.simd_level(), level);
      for (int threads : {1, 2}) {
        const int before = omp_get_max_threads();
        omp_set_num_threads(threads);
        expect_same_as_scalar(batched, scalar, s.x);
        omp_set_num_threads(before);
      }
    }
  }
}

TEST(AngleTerm, Avx2MatchesScalarTerm) { check_level(SimdLevel::Avx2); }
TEST(AngleTerm, Avx512MatchesScalarTerm) { check_level(SimdLevel::Avx512); }

TEST(AngleTerm, ScalarLevelIsTheStencilTerm) {
  const DeformedCloth s = deformed_cloth(9, 7, 0.2, 3);
  const AngleTerm term = shear_term(s.grid, SimdLevel::Scalar);
  const StencilTerm<AngleKernel> reference("shear", AngleKernel::shear(3.0, s.grid.spacing),
                                           grid_shear_corners(s.grid));
  VecX g = VecX::Zero(s.x.size()), g_reference = VecX::Zero(s.x.size());
  EXPECT_EQ(term.accumulate_gradient(s.x, g), reference.accumulate_gradient(s.x, g_reference));
  EXPECT_EQ(g, g_reference);
  EXPECT_EQ(term.energy(s.x), reference.energy(s.x));
}

TEST(AngleTerm, GeneralLayoutRunsScalar) {
  const DeformedCloth s = deformed_cloth(5, 5, 0.2, 4);
  AngleKernel general = AngleKernel::shear(3.0, s.grid.spacing);
  general.layout = AngleKernel::Layout::General;
  EXPECT_EQ(AngleTerm("shear", general, grid_shear_corners(s.grid)).simd_level(), SimdLevel::Scalar);
}

TEST(AngleTerm, DerivativesMatchFiniteDifferences) {
  const DeformedCloth s = deformed_cloth(12, 10, 0.2, 5);
  std::mt19937 rng(6);
  std::normal_distribution<double> normal(0.0, 1.0);
  VecX direction(s.x.size());
  for (Eigen::Index i = 0; i < direction.size(); ++i) direction[i] = normal(rng);
  testing::expect_derivatives_match_differences(shear_term(s.grid, best_simd_level()), s.x, direction);
  testing::expect_derivatives_match_differences(bend_term(s.grid, best_simd_level()), s.x, direction);
}

}  // namespace
}  // namespace fnopt
