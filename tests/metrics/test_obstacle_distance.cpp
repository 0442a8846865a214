// min_obstacle_distance: the smallest vertex distance over the frames, each frame's obstacles posed
// at its time, against the distance to a sphere written out by hand; a mesh's unsigned distance
// to the cloth against every pair of primitives tried.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/contact/additive_ccd.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/io/obj_mesh.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

TEST(ObstacleDistance, SmallestOverVerticesObstaclesAndFramesAtEachFramesPose) {
  Scene scene;
  scene.dt = 0.1;
  scene.obstacles = parse_obstacles("sphere center=0,0,0 radius=0.5 motion=xy_v2; plane point=0,0,-3 normal=0,0,1");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<Eigen::VectorXf> frames;
  double expected = INFINITY;
  for (int f = 0; f < 30; ++f) {
    Eigen::VectorXf x(3 * 20);
    for (int i = 0; i < x.size(); ++i) x[i] = static_cast<float>(u(rng));
    frames.push_back(x);
    const Vec3 centre = scene.obstacles[0].offset(f * scene.dt);  // the sphere's centre at rest is 0
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = x.segment<3>(3 * k).cast<double>();
      expected = std::min({expected, (p - centre).norm() - 0.5, p.z() + 3.0});
    }
  }
  EXPECT_NEAR(min_obstacle_distance(scene, frames), expected, 1e-12);
  EXPECT_EQ(min_obstacle_distance(Scene{}, frames), INFINITY);
}

// A rows x cols cloth of spacing 0.2 in the plane z = 0, each coordinate moved by up to `noise`.
VecX random_cloth(int rows, int cols, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-noise, noise);
  VecX x(3 * rows * cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) x.segment<3>(3 * (i * cols + j)) = Vec3(0.2 * j + u(rng), -0.2 * i + u(rng), u(rng));
  return x;
}

// `n` triangles on random vertices of [-0.2, 1.2] x [-1, 0.2] x [-0.5, 0.5], with one more vertex
// on no triangle, on the cloth.
TriangleMesh random_mesh(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> x(-0.2, 1.2), y(-1.0, 0.2), z(-0.5, 0.5);
  TriangleMesh mesh;
  for (int v = 0; v < 2 * n + 1; ++v) mesh.vertices.emplace_back(x(rng), y(rng), z(rng));
  std::uniform_int_distribution<int> vertex(0, 2 * n);
  while (static_cast<int>(mesh.triangles.size()) < n) {
    const std::array<int, 3> t = {vertex(rng), vertex(rng), vertex(rng)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) mesh.triangles.push_back(t);
  }
  mesh.vertices.emplace_back(0.2, -0.2, 0.0);  // on no triangle: not on the mesh's surface
  return mesh;
}

// The smallest distance over every cloth-vertex/mesh-triangle, mesh-vertex/cloth-triangle and
// cloth-edge/mesh-edge pair, the mesh's vertices given (only those on a triangle count).
double brute_force(const VecX& x, int rows, int cols, const std::vector<Vec3>& mesh,
                   const std::vector<std::array<int, 3>>& triangles) {
  std::vector<Vec3> cloth(rows * cols);
  for (int v = 0; v < rows * cols; ++v) cloth[v] = x.segment<3>(3 * v);
  std::vector<std::array<int, 3>> cloth_triangles;
  const auto grid_triangles = Grid{rows, cols, 1.0}.triangles();
  for (Eigen::Index f = 0; f < grid_triangles.rows(); ++f)
    cloth_triangles.push_back({grid_triangles(f, 0), grid_triangles(f, 1), grid_triangles(f, 2)});
  double smallest = INFINITY;
  for (const Vec3& p : cloth)
    for (const auto& t : triangles)
      smallest = std::min(smallest, ccd_distance::point_triangle_squared(p, mesh[t[0]], mesh[t[1]], mesh[t[2]]));
  for (const auto& m : triangles)
    for (const int v : m)
      for (const auto& t : cloth_triangles)
        smallest =
            std::min(smallest, ccd_distance::point_triangle_squared(mesh[v], cloth[t[0]], cloth[t[1]], cloth[t[2]]));
  for (const auto& a : unique_edges(cloth_triangles))
    for (const auto& b : unique_edges(triangles))
      smallest =
          std::min(smallest, ccd_distance::segment_segment_squared(cloth[a[0]], cloth[a[1]], mesh[b[0]], mesh[b[1]]));
  return std::sqrt(smallest);
}

// A two-frame sequence (the second frame's vertices moved apart), scaled and offset, between its
// frames: the search agrees with every pair tried, near the cloth, crossing it and far from it.
TEST(ObstacleDistance, AMeshsDistanceIsTheSmallestOfEveryPairOfPrimitives) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 40; ++trial) {
    const int rows = 3 + trial % 4, cols = 3 + trial % 5;
    const VecX x = random_cloth(rows, cols, 0.05, rng);
    TriangleMesh first = random_mesh(1 + trial % 13, rng), second = first;
    for (Vec3& v : second.vertices) v *= 1.2;
    const Vec3 offset(0.0, 0.0, 0.1 * (trial % 7) - 0.1);
    const auto shape = std::make_shared<const MeshShape>(MeshShape::sequence({first, second}, 10.0, 0.9, offset));
    const std::vector<Obstacle> obstacles = {Obstacle::mesh(shape, "/nowhere/mesh")};
    std::vector<Vec3> posed;
    obstacles[0].mesh_vertices(0.04, posed);
    const double expected = brute_force(x, rows, cols, posed, shape->triangles());
    EXPECT_NEAR(min_obstacle_distance(obstacles, x, rows, cols, 0.04), expected, 1e-12 * (1.0 + expected))
        << "trial " << trial;
  }
}

// Every frame's mesh posed at its time (a path moves it), beside an analytic obstacle.
TEST(ObstacleDistance, MeshesAndAnalyticObstaclesOverTheFrames) {
  const fnopt::testing::TempDir tmp;
  const std::string path = tmp.write("path.csv", "t,x,y,z\n0,0,0,2\n1,0,0,0\n");
  std::mt19937 rng(2);
  const TriangleMesh mesh = random_mesh(8, rng);
  Scene scene;
  scene.rows = 4, scene.cols = 6, scene.dt = 0.1;
  scene.obstacles = parse_obstacles("plane point=0,0,-1.5 normal=0,0,1");
  scene.obstacles.push_back(Obstacle::mesh(std::make_shared<const MeshShape>(MeshShape::single(mesh)), "/nowhere/m.obj")
                                .with_motion(ObstacleMotion::path(path)));
  std::vector<Eigen::VectorXf> frames;
  double expected = INFINITY;
  for (int f = 0; f < 11; ++f) {
    frames.push_back(random_cloth(4, 6, 0.05, rng).cast<float>());
    const VecX x = frames.back().cast<double>();
    std::vector<Vec3> posed;
    scene.obstacles[1].mesh_vertices(f * scene.dt, posed);
    expected = std::min(expected, brute_force(x, 4, 6, posed, mesh.triangles));
    for (int v = 0; v < 24; ++v) expected = std::min(expected, x[3 * v + 2] + 1.5);
    EXPECT_EQ(min_obstacle_distance(scene.obstacles, x, 4, 6, f * scene.dt),
              std::min(min_obstacle_distance({scene.obstacles[0]}, x, 4, 6, f * scene.dt),
                       min_obstacle_distance({scene.obstacles[1]}, x, 4, 6, f * scene.dt)));
  }
  EXPECT_NEAR(min_obstacle_distance(scene, frames), expected, 1e-12);
  EXPECT_TRUE(testing::throws_error([&] { min_obstacle_distance(scene.obstacles, VecX::Zero(9), 4, 6, 0.0); },
                                    "positions: holds 9 values"));
}

}  // namespace
}  // namespace fnopt
