// Bilinear resampling between grids of one cloth (cloth/grid_resampling.hpp): exact on fields
// linear in the rest coordinates (both directions, square and non-square grids of slightly
// different aspect ratios), constants stay constant, sizes are checked with clear errors.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/cloth/grid_resampling.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// c + A (x, z) per component, at the rest positions of `grid` (x = j h, z = -i h).
VecX linear_field(const Grid& grid, int components) {
  VecX f(components * grid.vertex_count());
  for (int i = 0; i < grid.rows; ++i)
    for (int j = 0; j < grid.cols; ++j)
      for (int c = 0; c < components; ++c) {
        const double x = j * grid.spacing, z = -i * grid.spacing;
        f[components * grid.index(i, j) + c] = 0.3 - 0.7 * c + (1.5 + c) * x + (2.0 - 0.5 * c) * z;
      }
  return f;
}

void expect_round_trip_exact(const Grid& a, const Grid& b, int components) {
  const VecX fa = linear_field(a, components), fb = linear_field(b, components);
  const VecX to_b = restrict_field(a, fa, b, components);
  EXPECT_LT((to_b - fb).cwiseAbs().maxCoeff(), 1e-12) << a.rows << "x" << a.cols << " -> " << b.rows << "x" << b.cols;
  const VecX back = prolong_field(b, to_b, a, components);
  EXPECT_LT((back - fa).cwiseAbs().maxCoeff(), 1e-12) << a.rows << "x" << a.cols << " <-> " << b.rows << "x" << b.cols;
}

TEST(GridResampling, LinearFieldsSurviveRestrictionAndProlongationExactly) {
  expect_round_trip_exact(Grid::make(64, 64, 1.0), Grid::make(32, 32, 1.0), 3);
  expect_round_trip_exact(Grid::make(32, 32, 1.0), Grid::make(64, 64, 1.0), 3);
  // Different aspect ratios (16/22 vs 31/44 of the long edge): extended boundary cells.
  expect_round_trip_exact(Grid::make(17, 23, 1.0), Grid::make(32, 45, 1.0), 3);
  expect_round_trip_exact(Grid::make(32, 45, 1.0), Grid::make(17, 23, 1.0), 3);
  expect_round_trip_exact(Grid::make(48, 80, 1.0), grid_with_longer_edge(Grid::make(48, 80, 1.0), 32), 1);
  expect_round_trip_exact(Grid::make(64, 32, 1.0), grid_with_longer_edge(Grid::make(64, 32, 1.0), 32), 2);
}

TEST(GridResampling, TheRestPoseOfOneGridIsTheRestPoseOfTheOther) {
  const Grid fine = Grid::make(100, 100, 1.0), coarse = Grid::make(32, 32, 1.0);
  EXPECT_LT((restrict_field(fine, fine.rest_positions(), coarse) - coarse.rest_positions()).cwiseAbs().maxCoeff(),
            1e-13);
}

TEST(GridResampling, ConstantsStayConstantAndSameGridIsTheIdentity) {
  const Grid fine = Grid::make(37, 29, 1.0), coarse = Grid::make(11, 9, 1.0);
  const VecX constant = VecX::Constant(3 * fine.vertex_count(), 0.625);
  EXPECT_LT((restrict_field(fine, constant, coarse).array() - 0.625).abs().maxCoeff(), 1e-15);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  VecX random(3 * fine.vertex_count());
  for (auto& value : random) value = normal(rng);
  EXPECT_LT((GridResampler(fine, fine).apply(random) - random).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(GridResampling, CoarseGridsKeepTheAspectRatio) {
  const Grid square = grid_with_longer_edge(Grid::make(100, 100, 1.0), 32);
  EXPECT_EQ(square.rows, 32);
  EXPECT_EQ(square.cols, 32);
  EXPECT_DOUBLE_EQ(square.spacing, 1.0 / 31);
  const Grid wide = grid_with_longer_edge(Grid::make(32, 64, 1.0), 32);
  EXPECT_EQ(wide.rows, 16);
  EXPECT_EQ(wide.cols, 32);
  const Grid tall = grid_with_longer_edge(Grid::make(80, 48, 1.0), 32);
  EXPECT_EQ(tall.rows, 32);
  EXPECT_EQ(tall.cols, 19);
  // Handles land on the matching coarse vertices.
  const Grid fine = Grid::make(64, 64, 1.0);
  EXPECT_EQ(nearest_vertex(square, fine, fine.index(0, 63)), square.index(0, 31));
  EXPECT_EQ(nearest_vertex(square, fine, fine.index(63, 0)), square.index(31, 0));
}

TEST(GridResampling, SizesAreCheckedWithClearErrors) {
  const Grid a = Grid::make(8, 8, 1.0), b = Grid::make(4, 5, 1.0);
  try {
    restrict_field(a, VecX::Zero(10), b);
    FAIL() << "no error for a field of the wrong size";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("grid resampling: the field has 10 values, expected 3 per vertex of the 8x8"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(restrict_field(a, VecX::Zero(192), b, 0), Error);
  EXPECT_THROW(GridResampler(Grid{1, 8, 0.1}, b), Error);
  EXPECT_THROW(GridResampler(a, Grid{4, 4, 0.0}), Error);
  EXPECT_THROW(grid_with_longer_edge(a, 2), Error);
}

}  // namespace
}  // namespace fnopt
