// The scene fields of contact (docs/design.md §14): obstacle lines (repeatable) and a ';' list as
// one setting, contact-*, handles = none, let-go and placement; their round trip through the scene
// text; and validation before any work, with one-line errors.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/simulation/simulator.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using testing::throws_error;

const char* kTwoObstacles =
    "res = 16\n"
    "handles = none\n"
    "placement = horizontal\n"
    "obstacle = sphere center=0,0,-0.5 radius=0.3 friction=0.2\n"
    "obstacle = plane point=0,0,-1 normal=0,0,1\n"
    "contact-stiffness = 20\n"
    "contact-range = 0.25\n"
    "contact-thickness = 0.002\n"
    "let-go = 0.5\n";

TEST(SceneObstacles, ObstacleLinesAddUpAndRoundTrip) {
  const Scene scene = load_scene_text(kTwoObstacles, "scene.txt");
  ASSERT_EQ(scene.obstacles.size(), 2u);
  EXPECT_EQ(scene.obstacles[0].shape(), ObstacleShape::Sphere);
  EXPECT_EQ(scene.obstacles[1].shape(), ObstacleShape::Plane);
  EXPECT_EQ(scene.contact.stiffness, 20.0);
  EXPECT_EQ(scene.contact.range_fraction, 0.25);
  EXPECT_EQ(scene.contact.thickness, 0.002);
  EXPECT_EQ(scene.handles, "none");
  EXPECT_EQ(scene.placement, Placement::Horizontal);
  EXPECT_EQ(scene.let_go, 0.5);
  const Scene back = load_scene_text(to_scene_text(scene), "rollout");
  ASSERT_EQ(back.obstacles.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(back.obstacles[k].to_text(), scene.obstacles[k].to_text());
  EXPECT_EQ(back.contact.stiffness, scene.contact.stiffness);
  EXPECT_EQ(back.contact.range_fraction, scene.contact.range_fraction);
  EXPECT_EQ(back.contact.thickness, scene.contact.thickness);
  EXPECT_EQ(back.placement, scene.placement);
  EXPECT_EQ(back.let_go, scene.let_go);
  EXPECT_EQ(to_scene_text(back), to_scene_text(scene));
  // Without obstacles the scene text has no contact lines.
  EXPECT_EQ(to_scene_text(Scene{}).find("obstacle"), std::string::npos);
}

// A path= file is relative to the scene file, and stored absolute, so the scene text reads back
// from anywhere.
TEST(SceneObstacles, PathFilesAreRelativeToTheSceneFile) {
  const std::filesystem::path directory = std::filesystem::path(::testing::TempDir()) / "obstacle_scene";
  std::filesystem::create_directories(directory);
  std::ofstream(directory / "lift.csv") << "t,x,y,z\n0,0.5,0.3,-0.5\n1,0.5,0.3,0\n";
  std::ofstream(directory / "scene.txt") << "obstacle = sphere center=0.5,0.3,-0.5 radius=0.1 path=lift.csv\n";
  const Scene scene = load_scene_file((directory / "scene.txt").string());
  ASSERT_EQ(scene.obstacles.size(), 1u);
  EXPECT_EQ(scene.obstacles[0].motion().name(), (directory / "lift.csv").string());
  EXPECT_LT((scene.obstacles[0].offset(0.5) - Vec3(0, 0, 0.25)).norm(), 1e-15);
  EXPECT_EQ(load_scene_text(to_scene_text(scene), "rollout").obstacles[0].to_text(), scene.obstacles[0].to_text());
  std::filesystem::remove_all(directory);
}

TEST(SceneObstacles, OneSettingTakesSeveralObstaclesSeparatedBySemicolons) {
  const Scene scene = apply_scene_settings(
      {}, {{"obstacle", "sphere center=0.5,0.3,-0.5 radius=0.1; capsule a=0,0.4,-1 b=1,0.4,-1 radius=0.05"},
           {"contact-thickness", "0.003"}});
  ASSERT_EQ(scene.obstacles.size(), 2u);
  EXPECT_EQ(scene.obstacles[1].shape(), ObstacleShape::Capsule);
  EXPECT_EQ(scene.contact.thickness, 0.003);
}

TEST(SceneObstacles, BadObstaclesAreRejectedBeforeAnyWork) {
  EXPECT_TRUE(throws_error([] { load_scene_text("obstacle = cube center=0,0,0\n", "s.txt"); },
                           "s.txt:1: obstacle: unknown shape 'cube'"));
  EXPECT_TRUE(throws_error([] { load_scene_text("obstacle = sphere center=0,0,0 radius=-1\n", "s.txt"); },
                           "s.txt:1: obstacle: sphere.radius"));
  const std::string file = ::testing::TempDir() + "scene_nan_path.csv";
  std::ofstream(file) << "0,0,0,0\nnan,0,0,0\n";
  EXPECT_TRUE(throws_error(
      [&] { apply_scene_settings({}, {{"obstacle", "sphere center=0,1,0 radius=0.1 path=" + file}}); }, "not finite"));
  std::remove(file.c_str());
  // The default cloth hangs in the x-z plane from (0,0,0) to (1,0,-1): vertex (2,3) of 16x16 is at
  // (0.2, 0, -0.1333).
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.obstacles = parse_obstacles("sphere center=0.2,0,-0.1333 radius=0.01");
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, "obstacle 1: the cloth starts inside it at vertex (2,3)"));
  EXPECT_TRUE(throws_error([&] { resolve(scene); }, "obstacle 1: the cloth starts inside it at vertex (2,3)"));
  // Within the thickness counts as inside; the second obstacle is named as the second.
  scene.obstacles = parse_obstacles("plane point=0,-1,0 normal=0,1,0; plane point=0,0.0005,0 normal=0,-1,0");
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, "obstacle 2: the cloth starts inside it at vertex (0,0)"));
  scene.contact.thickness = 0.0001;
  EXPECT_NO_THROW(scene.validate());
  EXPECT_TRUE(throws_error([] { load_scene_text("contact-range = -1\n", "s.txt"); }, "s.txt:1: contact-range"));
  EXPECT_TRUE(throws_error([] { load_scene_text("placement = diagonal\n", "s.txt"); }, "s.txt:1: placement"));
  EXPECT_TRUE(throws_error([] { load_scene_text("let-go = -2\n", "s.txt"); }, "s.txt:1: let-go"));
}

// A mesh through the hanging cloth, or around part of it, is refused naming the mesh, the feature
// and the cloth's vertex; a mesh relative to a scene file is read next to it.
TEST(SceneObstacles, AClothThroughOrInsideAMeshIsRejectedBeforeAnyWork) {
  const std::string dir = ::testing::TempDir();
  // A closed tetrahedron around (0.5, 0, -0.5): the cloth (y = 0) cuts through it.
  std::ofstream(dir + "scene_tetra.obj") << "v 0.4 -0.1 -0.6\nv 0.6 -0.1 -0.6\nv 0.5 0.1 -0.6\nv 0.5 0 -0.4\n"
                                           "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.obstacles = parse_obstacles("plane point=0,-1,0 normal=0,1,0; mesh file=" + dir + "scene_tetra.obj");
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, "obstacle 2: the cloth starts through it: "));
  // Moved off the cloth by 5 cm it is clear; a scene file names it relative to itself.
  std::ofstream(dir + "scene_mesh.scene") << "obstacle = mesh file=scene_tetra.obj offset=0,-0.2,0\n";
  const Scene loaded = load_scene_file(dir + "scene_mesh.scene");
  ASSERT_EQ(loaded.obstacles.size(), 1u);
  EXPECT_EQ(loaded.obstacles[0].mesh_source(), dir + "scene_tetra.obj");
  EXPECT_NO_THROW(loaded.validate());
  // A large box around the whole cloth's lower rows: the vertices inside are refused.
  std::ofstream(dir + "scene_box.obj") << "v -1 -1 -2\nv 2 -1 -2\nv 2 1 -2\nv -1 1 -2\n"
                                         "v -1 -1 -0.55\nv 2 -1 -0.55\nv 2 1 -0.55\nv -1 1 -0.55\n"
                                         "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
  scene.obstacles = parse_obstacles("mesh file=" + dir + "scene_box.obj");
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, "obstacle 1: the cloth starts inside it at vertex (9,0)"));
}

TEST(SceneObstacles, HorizontalPlacementIsCentredInTheXYPlane) {
  const Grid grid = Grid::make(5, 9, 1.0);
  const VecX rest = placed_rest_positions(grid, Placement::Horizontal);
  const auto points = rest.reshaped(3, grid.vertex_count());
  EXPECT_LT(points.row(2).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT(points.rowwise().mean().norm(), 1e-12);
  // The same grid distances as the vertical rest pose: a rigid motion of it.
  const VecX vertical = grid.rest_positions();
  for (int a = 0; a < grid.vertex_count(); a += 7)
    for (int b = 0; b < grid.vertex_count(); b += 5)
      EXPECT_NEAR((vertex(rest, a) - vertex(rest, b)).norm(), (vertex(vertical, a) - vertex(vertical, b)).norm(), 1e-12);
}

// let-go: the handles follow their motion until the let-go time, then the cloth falls freely (its
// former handles accelerate at g like the rest).
TEST(SceneObstacles, LetGoReleasesEveryHandle) {
  Scene scene;
  scene.rows = scene.cols = 8;
  scene.frames = 30;
  scene.motion = "static";
  scene.let_go = 0.25;
  const ResolvedScene setup = resolve(scene);
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  Simulator simulator(setup, newton, options);
  const int handle = setup.handles.vertices[0];
  const Vec3 start = vertex(simulator.positions(), handle);
  for (int step = 0; step < 15; ++step) simulator.step();  // t = 0.25 s
  EXPECT_FALSE(simulator.handles_released());
  EXPECT_LT((vertex(simulator.positions(), handle) - start).norm(), 1e-12);
  for (int step = 0; step < 15; ++step) simulator.step();
  EXPECT_TRUE(simulator.handles_released());
  EXPECT_LT(vertex(simulator.positions(), handle).z(), start.z() - 0.05);
}

}  // namespace
}  // namespace fnopt
