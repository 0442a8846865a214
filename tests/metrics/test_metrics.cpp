// The error metrics of docs/design.md §8: the k-d tree against brute force, e_CD (self, shifts,
// the 2 d^2 of a rigid normal shift), e_3D against a hand computation, frame time matching
// (ARCSim's 1/30 s against fnopt's 1/60 s), and the per-step error on a small Newton rollout.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/metrics/chamfer.hpp>
#include <fnopt/metrics/frame_matching.hpp>
#include <fnopt/metrics/kd_tree.hpp>
#include <fnopt/metrics/step_error.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

std::vector<Vec3> random_points(int n, unsigned seed, double scale = 1.0) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-scale, scale);
  std::vector<Vec3> points(n);
  for (auto& p : points) p = Vec3(uniform(random), uniform(random), uniform(random));
  return points;
}

TEST(KdTree3, NearestNeighbourEqualsBruteForce) {
  std::vector<Vec3> points = random_points(2000, 1);
  points.push_back(points[5]);  // a duplicate
  for (int k = 0; k < 50; ++k) points.push_back(Vec3(0.5, 0.25, -0.125));  // many equal points
  const KdTree3 tree(points);
  for (const Vec3& q : random_points(1000, 2, 1.3)) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) best = std::min(best, (p - q).squaredNorm());
    const auto found = tree.nearest(q);
    ASSERT_GE(found.index, 0);
    EXPECT_EQ(found.squared_distance, best);
    EXPECT_EQ((points[found.index] - q).squaredNorm(), best);
  }
  EXPECT_EQ(KdTree3({}).nearest(Vec3::Zero()).index, -1);
}

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
  const double cd = mesh_chamfer_distance(coarse.rest_positions(), coarse.triangles(), fine.rest_positions(),
                                          fine.triangles());
  EXPECT_LT(cd, 1.5e-4);  // the same plane: only the sampling floor
  EXPECT_TRUE(std::isnan(chamfer_distance({Vec3::Zero()}, {Vec3(NAN, 0, 0)})));
  ChamferOptions bad;
  bad.samples = 0;
  EXPECT_ANY_THROW(bad.validate());
}

TrajectoryFrames trajectory(const Grid& grid, int frames, double dt, double drift) {
  TrajectoryFrames t;
  t.rows = grid.rows;
  t.cols = grid.cols;
  for (int k = 0; k < frames; ++k) {
    VecX x = grid.rest_positions();
    for (int v = 0; v < grid.vertex_count(); ++v) x[3 * v + 1] -= drift * k;  // along the normal
    t.times.push_back(k * dt);
    t.positions.push_back(x.cast<float>());
  }
  return t;
}

TEST(TrajectoryError, RelativeFrameErrorMatchesAHandComputation) {
  Eigen::VectorXf reference(6), x(6);
  reference << 1, 2, 2, 0, 0, 0;  // norm 3
  x << 1, 2, 2, 0, 0, 1.5;          // differs by 1.5 in one coordinate
  EXPECT_NEAR(relative_frame_error(x, reference), 0.5, 1e-7);

  // Two frames: errors 0 and 0.5, mean 0.25.
  TrajectoryFrames ref, roll;
  ref.rows = roll.rows = 1;
  ref.cols = roll.cols = 2;
  ref.times = roll.times = {0.0, 0.1};
  ref.positions = {reference, reference};
  roll.positions = {reference, x};
  TrajectoryComparisonOptions options;
  options.chamfer_enabled = false;
  const TrajectoryComparison c = compare_trajectories(ref, roll, -1.0, options);
  ASSERT_EQ(c.matches.size(), 2u);
  EXPECT_TRUE(c.correspondence);
  EXPECT_NEAR(c.e3d, 0.25, 1e-7);
}

TEST(FrameMatching, PairsArcsimFramesWithEverySecondFnoptFrame) {
  std::vector<double> arcsim, fnopt;
  for (int k = 0; k < 196; ++k) arcsim.push_back(k / 30.0);
  for (int k = 0; k <= 390; ++k) fnopt.push_back(k * (1.0 / 60.0));
  const auto matches = match_frames(arcsim, fnopt);
  ASSERT_EQ(matches.size(), 196u);
  for (int k = 0; k < 196; ++k) {
    EXPECT_EQ(matches[k].reference, k);
    EXPECT_EQ(matches[k].rollout, 2 * k);
  }
  // A rollout that diverged after 100 steps: only the frames it has.
  fnopt.resize(101);
  EXPECT_EQ(match_frames(arcsim, fnopt).size(), 51u);
  // The same times match one to one; times must not decrease.
  EXPECT_EQ(match_frames(fnopt, fnopt).size(), fnopt.size());
  EXPECT_ANY_THROW(match_frames({0.0, 0.2, 0.1}, fnopt));
}

TEST(TrajectoryError, ComparesAcrossRatesAndResolutions) {
  const Grid g32 = Grid::make(9, 9, 1.0), g16 = Grid::make(5, 5, 1.0);
  const TrajectoryFrames reference = trajectory(g32, 20, 1.0 / 30.0, 0.0);
  const TrajectoryFrames rollout = trajectory(g16, 39, 1.0 / 60.0, 0.001);  // moves 1 mm per step
  const TrajectoryComparison c = compare_trajectories(reference, rollout, g16.spacing);
  EXPECT_EQ(c.matches.size(), 20u);
  EXPECT_FALSE(c.correspondence);
  EXPECT_TRUE(std::isnan(c.e3d));
  // Frame k (t = k/30) of the rollout moved 2k mm along the normal: CD ~ 2 (2k mm)^2 plus the sampling floor.
  double expected = 0.0;
  for (int k = 0; k < 20; ++k) expected += 2 * std::pow(0.002 * k, 2) / 20;
  EXPECT_NEAR(c.chamfer, expected, 0.1 * expected + 1.5e-4);
  EXPECT_NEAR(c.max_strain, 0.0, 1e-6);
  EXPECT_NE(c.describe_matching().find("20 of 20"), std::string::npos);
}

TEST(StepError, IsZeroForNewtonAndBetweenZeroAndOneForAFewGdIterations) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 12;
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  const RolloutResult rollout = run_rollout(resolve(scene), newton, options);
  TrajectoryFrames reference;
  reference.rows = reference.cols = 8;
  reference.times = rollout.times;
  reference.positions = rollout.positions;
  StepErrorBench bench(scene, reference, 4);
  EXPECT_EQ(bench.steps().size(), 4u);

  NewtonOptimizer again;
  const StepErrorSummary exact = bench.evaluate(again, NewtonOptimizer::reference_solve_options());
  EXPECT_NEAR(exact.mean, 0.0, 1e-6);
  GradientDescentOptimizer gd;
  const StepErrorSummary rough = bench.evaluate(gd, {3, 0.0});
  for (const auto& sample : rough.samples) {
    EXPECT_GT(sample.error, 0.0);
    EXPECT_LT(sample.error, 1.0);
  }
  // A reference without a frame every step is refused.
  TrajectoryFrames sparse = reference;
  for (double& t : sparse.times) t *= 2;
  EXPECT_ANY_THROW(StepErrorBench(scene, sparse, 4));
}

}  // namespace
}  // namespace fnopt
