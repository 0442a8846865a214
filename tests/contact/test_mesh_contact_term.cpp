// The mesh contact term: the energy on its candidates equal to the energy summed over every pair of
// cloth and mesh primitives, its gradient and Hessian (friction included) against finite
// differences, CCD that stops the cloth before a mesh's corner pokes through a triangle or its
// ridge cuts between two vertices, the start carried by a moving mesh (over a vertex, a corner through
// a triangle, a ridge through edges), and the winding-number test
// of a vertex inside a closed mesh.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>
#include <random>

#include <fnopt/cloth/hessian_assembly.hpp>
#include <fnopt/contact/contact_term.hpp>
#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/contact/self_contact_kernel.hpp>
#include <fnopt/metrics/mesh_intersections.hpp>
#include "tests/util/energy_term_derivatives.hpp"
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

// The test cloth: 8 x 8 over 0.1 m, hanging in the x-z plane (vertex (i, j) at (j h, 0, -i h)).
Grid test_grid() { return Grid::make(8, 8, 0.1); }

Obstacle mesh_obstacle(const TriangleMesh& mesh, double friction = 0.0) {
  Obstacle o = Obstacle::mesh(std::make_shared<const MeshShape>(MeshShape::single(mesh)), "/test/mesh.obj");
  o.with_friction(friction);
  return o;
}

// A closed pyramid below the cloth (y < 0) whose apex, `gap` below the cloth, points up (+y) at the
// centroid of the cloth triangle (3,3)-(4,4)-(3,4).
TriangleMesh pyramid(const Grid& grid, double gap) {
  const double h = grid.spacing;
  const Vec3 apex((3 + 4 + 4) / 3.0 * h, -gap, -(3 + 4 + 3) / 3.0 * h);
  TriangleMesh mesh;
  mesh.vertices = {apex,
                   apex + Vec3(-0.03, -0.03, 0.03),
                   apex + Vec3(0.03, -0.03, 0.03),
                   apex + Vec3(0.03, -0.03, -0.03),
                   apex + Vec3(-0.03, -0.03, -0.03)};
  // Counter-clockwise seen from outside.
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {1, 2, 3}, {1, 3, 4}};
  return mesh;
}

// A closed prism below the cloth whose ridge, `gap` below it, runs along x at z = -3.5 h, between
// the cloth's rows 3 and 4 (so it crosses their edges, not their vertices).
TriangleMesh ridge(const Grid& grid, double gap) {
  const double z = -3.5 * grid.spacing;
  TriangleMesh mesh;
  mesh.vertices = {{-0.02, -gap, z}, {0.12, -gap, z}, {-0.02, -0.05, z - 0.02}, {0.12, -0.05, z - 0.02},
                   {-0.02, -0.05, z + 0.02}, {0.12, -0.05, z + 0.02}};
  mesh.triangles = {{0, 1, 3}, {0, 3, 2}, {0, 4, 5}, {0, 5, 1}, {2, 3, 5}, {2, 5, 4}, {0, 2, 4}, {1, 5, 3}};
  return mesh;
}

Vec12 stencil(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec12 s;
  s << a, b, c, d;
  return s;
}

// The barrier summed over every pair of cloth and mesh primitives, by brute force.
double every_pair_energy(const MeshContactTerm& term, const VecX& x, const VecX& rest) {
  const ContactParams& params = term.params();
  const PointTriangleBarrier pt{params.stiffness, term.range(), params.thickness};
  const std::vector<Vec3>& m = term.mesh_vertices();
  auto p = [](const VecX& y, int v) { return Vec3(y.segment<3>(3 * v)); };
  double total = 0.0;
  for (int v = 0; v < static_cast<int>(x.size() / 3); ++v)
    for (const auto& t : term.mesh_triangles()) total += pt.energy(stencil(p(x, v), m[t[0]], m[t[1]], m[t[2]]));
  for (std::size_t k = 0; k < m.size(); ++k)
    for (const auto& t : term.cloth_triangles()) total += pt.energy(stencil(m[k], p(x, t[0]), p(x, t[1]), p(x, t[2])));
  for (const auto& a : term.cloth_edges())
    for (const auto& b : term.mesh_edges()) {
      const EdgeEdgeBarrier ee{params.stiffness, term.range(), params.thickness,
                               edge_edge_mollifier_threshold(stencil(p(rest, a[0]), p(rest, a[1]), m[b[0]], m[b[1]]))};
      total += ee.energy(stencil(p(x, a[0]), p(x, a[1]), m[b[0]], m[b[1]]));
    }
  return total;
}

// The cloth at rest moved by `shift`.
VecX shifted(const Grid& grid, const Vec3& shift) {
  VecX x = grid.rest_positions();
  for (int v = 0; v < grid.vertex_count(); ++v) x.segment<3>(3 * v) += shift;
  return x;
}

TEST(MeshContactTerm, TheEnergyOnTheCandidatesIsTheEnergyOfEveryPair) {
  const Grid grid = test_grid();
  MeshContactTerm term(grid, {mesh_obstacle(pyramid(grid, 0.004)), mesh_obstacle(ridge(grid, 0.006))}, {});
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 5e-4);
  const VecX rest = grid.rest_positions();
  term.begin_step(rest, rest, 0.0, 0.01);
  for (double lift : {0.0, 0.001, -0.0015, 0.004, 0.02}) {
    VecX x = shifted(grid, Vec3(0.0, lift, 0.0));
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
    const double expected = every_pair_energy(term, x, rest);
    EXPECT_NEAR(term.energy(x), expected, 1e-12 * std::max(1.0, expected)) << lift;
  }
  EXPECT_GT(every_pair_energy(term, rest, rest), 0.0);
}

TEST(MeshContactTerm, GradientAndHessianMatchFiniteDifferencesWithFriction) {
  const Grid grid = test_grid();
  MeshContactTerm term(grid, {mesh_obstacle(pyramid(grid, 0.003), 0.5), mesh_obstacle(ridge(grid, 0.004), 0.3)}, {});
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 3e-4);
  const VecX start = grid.rest_positions();
  VecX x = start;
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
  term.begin_step(start, x, 0.0, 0.01);
  ASSERT_GT(term.friction_pair_count(), 0);
  ASSERT_GT(term.barrier_energy(x), 0.0);
  const VecX direction = VecX::NullaryExpr(x.size(), [&] { return noise(random); }).normalized();
  testing::expect_derivatives_match_differences(term, x, direction);

  std::vector<int> free_index(grid.vertex_count());
  for (int v = 0; v < grid.vertex_count(); ++v) free_index[v] = v;
  HessianAssembly assembly(free_index);
  const int handle = term.register_hessian(assembly);
  assembly.finalize();
  // The projected Hessian is positive semi-definite.
  assembly.set_zero();
  term.accumulate_hessian(x, true, assembly, handle);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(assembly.matrix());
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues().minCoeff(), -1e-9 * dense.norm());
}

// Pushing the cloth straight down onto each mesh: CCD stops it before the apex pokes through a
// triangle or the ridge cuts between two rows, with no crossing on the way.
TEST(MeshContactTerm, CcdStopsTheClothBeforeACornerOrARidgeGoesThrough) {
  const Grid grid = test_grid();
  for (const bool corner : {true, false}) {
    const TriangleMesh mesh = corner ? pyramid(grid, 0.01) : ridge(grid, 0.01);
    const MeshContactTerm term(grid, {mesh_obstacle(mesh)}, {});
    const VecX from = grid.rest_positions(), to = shifted(grid, Vec3(0.0, -0.02, 0.0));
    std::vector<Eigen::Vector3i> triangles;
    for (const auto& f : mesh.triangles) triangles.emplace_back(f[0], f[1], f[2]);
    ASSERT_GT(count_mesh_intersections(to.cast<float>(), grid.rows, grid.cols, mesh.vertices, triangles), 0)
        << "the move goes through the mesh";
    const double s = term.safe_fraction(from, to);
    EXPECT_GT(s, 0.0) << corner;
    EXPECT_LT(s, 0.5) << corner;  // the mesh is reached at s = 0.5
    const VecX stop = from + s * (to - from);
    MeshContactPair pair;
    EXPECT_GE(term.closest_pair(stop, pair), term.params().thickness) << corner;
    EXPECT_EQ(count_mesh_intersections(stop.cast<float>(), grid.rows, grid.cols, mesh.vertices, triangles), 0);
    EXPECT_EQ(term.safe_fraction(from, shifted(grid, Vec3(0.0, 0.02, 0.0))), 1.0) << "moving away is safe";
  }
}

// The start of a step over which `mesh` moves 2 cm up (+y) through the resting test cloth, carried:
// the mesh's end pose must cross the cloth at rest (exact crossings), and the carried start must
// cross nothing and be clear of it by the thickness.
VecX carried_start(const Grid& grid, const TriangleMesh& mesh) {
  MeshContactTerm term(grid, {mesh_obstacle(mesh)}, {});
  ObstacleOffsets offsets{{Vec3::Zero()}, {Vec3(0.0, 0.02, 0.0)}};
  const VecX rest = grid.rest_positions();
  term.begin_step(rest, rest, 0.0, 0.01, &offsets);
  std::vector<Vec3> end_pose = mesh.vertices;
  for (Vec3& p : end_pose) p.y() += 0.02;
  std::vector<Eigen::Vector3i> triangles;
  for (const auto& f : mesh.triangles) triangles.emplace_back(f[0], f[1], f[2]);
  EXPECT_GT(count_mesh_intersections(rest.cast<float>(), grid.rows, grid.cols, end_pose, triangles), 0)
      << "the mesh's end pose goes through the cloth";
  VecX safe;
  term.safe_start_positions(rest, safe);
  MeshContactPair pair;
  EXPECT_GE(term.closest_pair(safe, pair), term.params().thickness);
  EXPECT_EQ(count_mesh_intersections(safe.cast<float>(), grid.rows, grid.cols, end_pose, triangles), 0);
  return safe;
}

// A pyramid moving up through the resting cloth over the step: the start carries the vertices it
// would sweep over, and the carried start is outside the mesh's end pose.
TEST(MeshContactTerm, TheStartIsCarriedByAMovingMesh) {
  const Grid grid = test_grid();
  EXPECT_GT((carried_start(grid, pyramid(grid, 0.01)) - grid.rest_positions()).norm(), 0.0);
}

// A needle 1 mm thick whose tip, 5 mm behind the cloth, passes through a cloth triangle's middle
// within the step, sweeping over no cloth vertex: the triangle is carried with the tip.
TEST(MeshContactTerm, AThinCornerSweepingThroughAClothTriangleCarriesIt) {
  const Grid grid = test_grid();
  const double h = grid.spacing;
  const Vec3 tip((3 + 4 + 4) / 3.0 * h, -0.005, -(3 + 4 + 3) / 3.0 * h);
  TriangleMesh needle;
  needle.vertices = {tip, tip + Vec3(-0.0005, -0.05, 0.0005), tip + Vec3(0.0005, -0.05, 0.0005),
                     tip + Vec3(0.0, -0.05, -0.0005)};
  needle.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {1, 2, 3}};
  const VecX safe = carried_start(grid, needle);
  for (const auto& [i, j] : {std::pair{3, 3}, std::pair{4, 4}, std::pair{3, 4}})
    EXPECT_NEAR(safe[3 * grid.index(i, j) + 1], 0.02, 1e-12) << i << "," << j;  // the triangle, carried
  EXPECT_EQ(safe[3 * grid.index(0, 0) + 1], 0.0);                               // the rest stays
}

// A blade 1 mm thick whose ridge, 5 mm behind the cloth and along x between rows 3 and 4, passes
// through the cloth within the step: its faces sweep over no cloth vertex and its ends lie beyond the
// cloth, so only the ridge cuts the edges between the two rows, and they are carried with it.
TEST(MeshContactTerm, ARidgeSweepingThroughClothEdgesCarriesThem) {
  const Grid grid = test_grid();
  const double z = -3.5 * grid.spacing;
  TriangleMesh blade;
  blade.vertices = {{-0.02, -0.005, z}, {0.12, -0.005, z}, {-0.02, -0.055, z - 0.0005}, {0.12, -0.055, z - 0.0005},
                    {-0.02, -0.055, z + 0.0005}, {0.12, -0.055, z + 0.0005}};
  blade.triangles = {{0, 1, 3}, {0, 3, 2}, {0, 4, 5}, {0, 5, 1}, {2, 3, 5}, {2, 5, 4}, {0, 2, 4}, {1, 5, 3}};
  const VecX safe = carried_start(grid, blade);
  for (int j = 0; j < grid.cols; ++j) {
    EXPECT_NEAR(safe[3 * grid.index(3, j) + 1], 0.02, 1e-12) << j;  // the cut edges' ends, carried
    EXPECT_NEAR(safe[3 * grid.index(4, j) + 1], 0.02, 1e-12) << j;
    EXPECT_EQ(safe[3 * grid.index(0, j) + 1], 0.0) << j;  // the rest stays
  }
}

TEST(MeshContactTerm, AFarMeshHasNoCandidateAndCostsABoxTest) {
  const Grid grid = test_grid();
  MeshContactTerm term(grid, {mesh_obstacle(pyramid(grid, 1.0))}, {});
  const VecX rest = grid.rest_positions();
  term.begin_step(rest, rest, 0.0, 0.01);
  EXPECT_TRUE(term.candidates().empty());
  EXPECT_EQ(term.energy(rest), 0.0);
  EXPECT_FALSE(term.may_touch(Vec3(0.0, -0.1, -0.1), Vec3(0.1, 0.0, 0.0)));
  EXPECT_EQ(term.safe_fraction(rest, shifted(grid, Vec3(0.0, -0.1, 0.0))), 1.0);
}

TEST(MeshContactTerm, AVertexInsideAClosedMeshIsFound) {
  const Grid grid = test_grid();
  const MeshContactTerm term(grid, {mesh_obstacle(ridge(grid, 0.01)), mesh_obstacle(pyramid(grid, -0.01))}, {});
  // The pyramid's apex is 1 cm above the cloth: the vertices under it are inside.
  const VecX rest = grid.rest_positions();
  EXPECT_EQ(term.enclosing_mesh(rest, grid.index(3, 4)), 1);
  EXPECT_EQ(term.enclosing_mesh(rest, grid.index(0, 0)), -1);
  EXPECT_EQ(term.enclosing_mesh(shifted(grid, Vec3(0.0, -0.04, 0.0)), grid.index(3, 3)), 0);
}

TEST(MeshContactTerm, RefusesAnAnalyticObstacle) {
  const Grid grid = test_grid();
  EXPECT_TRUE(testing::throws_error([&] { MeshContactTerm(grid, {Obstacle::sphere(Vec3::Zero(), 1.0)}, {}); },
                                    "obstacles: a mesh contact term takes meshes only"));
}

}  // namespace
}  // namespace fnopt
