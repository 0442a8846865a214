// e_CD of docs/design.md §8: of a mesh with itself, its sampling, shifts (the 2 d^2 of a rigid
// normal shift) and across resolutions.
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/metrics/chamfer.hpp>

namespace fnopt {
namespace {

// A flat 1 m x 1 m cloth (the benchmark's rest pose) and a draped variant.
struct Meshes {
  Grid grid = Grid::make(16, 16, 1.0);
  Triangles triangles = grid.triangles();
  VecX rest = grid.rest_positions();
};

TEST(Chamfer, OfAMeshWithItselfIsZeroAndSmallWithIndependentSamples) {
  Meshes m;
  EXPECT_EQ(mesh_chamfer_distance(m.rest, m.triangles, m.rest, m.triangles), 0.0);
  // Independent samples (pytorch3d's way): the sampling floor ~ 2/(pi * 10^4) = 6.4e-5 on 1 m^2.
  const auto a = sample_mesh_surface(m.rest, m.triangles, 10000, 1);
  const auto b = sample_mesh_surface(m.rest, m.triangles, 10000, 2);
  const double floor = chamfer_distance(a, b);
  EXPECT_GT(floor, 3e-5);
  EXPECT_LT(floor, 1.2e-4);
}

TEST(Chamfer, SamplesLieOnTheMeshUniformlyByArea) {
  Meshes m;
  VecX stretched = m.rest;
  for (int k = 0; k < m.grid.vertex_count(); ++k)
    if (stretched[3 * k] > 0.5) stretched[3 * k] = 0.5 + 3.0 * (stretched[3 * k] - 0.5);  // right half 3x wider
  const auto points = sample_mesh_surface(stretched, m.triangles, 20000, 7);
  int right = 0;
  for (const Vec3& p : points) {
    EXPECT_NEAR(p.y(), 0.0, 1e-12);
    right += p.x() > 0.5;
  }
  EXPECT_NEAR(right / 20000.0, 0.75, 0.015);  // areas 0.5 and 1.5
}

TEST(Chamfer, GrowsWithAShiftAndIsTwiceTheSquaredNormalShift) {
  Meshes m;
  double previous = 0.0;
  for (double d : {0.005, 0.01, 0.02, 0.05}) {
    VecX shifted = m.rest;
    for (int k = 0; k < m.grid.vertex_count(); ++k) shifted[3 * k] += d;  // in the cloth's plane
    const double cd = mesh_chamfer_distance(m.rest, m.triangles, shifted, m.triangles);
    EXPECT_GT(cd, previous) << "shift " << d;
    previous = cd;
  }
  // Shifted along the normal by d: every nearest point is d away (plus the in-plane sampling
  // gap, zero with common random numbers): CD = 2 d^2.
  for (double d : {0.01, 0.1}) {
    VecX lifted = m.rest;
    for (int k = 0; k < m.grid.vertex_count(); ++k) lifted[3 * k + 1] += d;
    const double cd = mesh_chamfer_distance(m.rest, m.triangles, lifted, m.triangles);
    EXPECT_NEAR(cd, 2 * d * d, 1e-9) << "normal shift " << d;
    // Independent samples: 2 d^2 plus the sampling floor, within 1 % for d = 0.1.
    const double independent = chamfer_distance(sample_mesh_surface(m.rest, m.triangles, 10000, 3),
                                                sample_mesh_surface(lifted, m.triangles, 10000, 4));
    if (d == 0.1) {
      EXPECT_NEAR(independent, 2 * d * d, 0.01 * 2 * d * d);
    }
  }
}

TEST(Chamfer, WorksAcrossResolutionsAndRejectsNonFinitePoints) {
  const Grid coarse = Grid::make(8, 8, 1.0), fine = Grid::make(31, 31, 1.0);
  const double cd =
      mesh_chamfer_distance(coarse.rest_positions(), coarse.triangles(), fine.rest_positions(), fine.triangles());
  EXPECT_LT(cd, 1.5e-4);  // the same plane: only the sampling floor
  EXPECT_TRUE(std::isnan(chamfer_distance({Vec3::Zero()}, {Vec3(NAN, 0, 0)})));
  ChamferOptions bad;
  bad.samples = 0;
  EXPECT_ANY_THROW(bad.validate());
}

}  // namespace
}  // namespace fnopt
