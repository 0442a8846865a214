// The scene file format: parsing, paths, precedence, line-numbered errors, round trip.
#include <gtest/gtest.h>

#include <filesystem>

#include <fnopt/scenes/scene.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

using testing::TempDir;
using testing::throws_error;

void expect_same_scene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.cols, b.cols);
  EXPECT_EQ(a.size, b.size);
  EXPECT_EQ(a.grid_units_of, b.grid_units_of);
  EXPECT_EQ(a.material_name, b.material_name);
  EXPECT_EQ(a.material.stretch, b.material.stretch);
  EXPECT_EQ(a.material.shear, b.material.shear);
  EXPECT_EQ(a.material.bend, b.material.bend);
  EXPECT_EQ(a.material.density, b.material.density);
  EXPECT_EQ(a.material.damping, b.material.damping);
  EXPECT_EQ(a.handles, b.handles);
  EXPECT_EQ(a.handle_vertices, b.handle_vertices);
  EXPECT_EQ(a.motion, b.motion);
  EXPECT_EQ(a.trajectory, b.trajectory);
  EXPECT_EQ(a.speed, b.speed);
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_EQ(a.repulsion, b.repulsion);
  EXPECT_EQ(a.material.repulsion, b.material.repulsion);
  EXPECT_EQ(a.material.repulsion_stiffness, b.material.repulsion_stiffness);
  EXPECT_EQ(a.material.repulsion_range, b.material.repulsion_range);
}

TEST(SceneFile, ReadsEveryKeyWithCommentsAndBlankLines) {
  TempDir dir;
  const auto path = dir.write("scene.txt",
                              "# a scene\n"
                              "\n"
                              "rows = 40   # trailing comment\n"
                              "cols=24\n"
                              "  size = 1.5\n"
                              "material = default\n"
                              "stretch = 55\n"
                              "shear = 4.5\n"
                              "bend = 3e-5\n"
                              "density = 0.2\n"
                              "damping = 0.1\n"
                              "handles = diagonal\n"
                              "handle-vertices = 0,0; 39,23\n"
                              "motion = rot_h1_opp\n"
                              "speed = 1.2\n"
                              "dt = 1/120\n"
                              "frames = 10\n"
                              "gravity = 0, 0, -1.62\n"
                              "repulsion = true\n"
                              "repulsion-stiffness = 2.5\n"
                              "repulsion-range = 0.75\n");
  const Scene scene = load_scene_file(path);
  EXPECT_EQ(scene.rows, 40);
  EXPECT_EQ(scene.cols, 24);
  EXPECT_EQ(scene.size, 1.5);
  EXPECT_EQ(scene.material_name, "default");
  EXPECT_EQ(scene.material.stretch, 55.0);
  EXPECT_EQ(scene.material.shear, 4.5);
  EXPECT_EQ(scene.material.bend, 3e-5);
  EXPECT_EQ(scene.material.density, 0.2);
  EXPECT_EQ(scene.material.damping, 0.1);
  EXPECT_EQ(scene.handles, "diagonal");
  EXPECT_EQ(scene.handle_vertices, "0,0; 39,23");
  EXPECT_EQ(scene.motion, "rot_h1_opp");
  EXPECT_EQ(scene.speed, 1.2);
  EXPECT_EQ(scene.dt, 1.0 / 120);
  EXPECT_EQ(scene.frames, 10);
  EXPECT_EQ(scene.gravity, Vec3(0, 0, -1.62));
  EXPECT_EQ(scene.repulsion, RepulsionMode::On);
  EXPECT_TRUE(scene.material.repulsion);
  EXPECT_EQ(scene.material.repulsion_stiffness, 2.5);
  EXPECT_EQ(scene.material.repulsion_range, 0.75);
  EXPECT_NO_THROW(resolve(scene));
}

TEST(SceneFile, ResSetsRowsAndColsAndUnsetKeysKeepTheBase) {
  TempDir dir;
  Scene base;
  base.frames = 7;
  base.motion = "xz_v2";
  const Scene scene = load_scene_file(dir.write("s.txt", "res = 64\n"), base);
  EXPECT_EQ(scene.rows, 64);
  EXPECT_EQ(scene.cols, 64);
  EXPECT_EQ(scene.frames, 7);
  EXPECT_EQ(scene.motion, "xz_v2");
}

TEST(SceneFile, MaterialResetsValuesAndLaterKeysOverrideThem) {
  TempDir dir;
  const Scene overridden = load_scene_file(dir.write("a.txt", "material = default\nstretch = 50\n"));
  EXPECT_EQ(overridden.material.stretch, 50.0);
  EXPECT_EQ(overridden.material.density, Material{}.density);
  const Scene reset = load_scene_file(dir.write("b.txt", "stretch = 50\nmaterial = default\n"));
  EXPECT_EQ(reset.material.stretch, Material{}.stretch);
}

TEST(SceneFile, MaterialAndTrajectoryFilesAreFoundNextToTheSceneFile) {
  TempDir dir;
  std::filesystem::create_directory(dir.path() / "scenes");
  dir.write("scenes/knit.material", "stretch = 12\ndensity = 0.3\n");
  dir.write("scenes/motions.csv",
            "motion,t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z\n"
            "up,0,0,0,0,1,0,0\n");
  const auto path = dir.write("scenes/s.txt",
                              "material = knit.material\n"
                              "trajectory = motions.csv#up\n");
  const Scene scene = load_scene_file(path);
  EXPECT_EQ(scene.material.stretch, 12.0);
  EXPECT_EQ(scene.material.density, 0.3);
  EXPECT_EQ(scene.trajectory, (dir.path() / "scenes" / "motions.csv").string() + "#up");
  EXPECT_NO_THROW(resolve(scene));
}

TEST(SceneFile, LaterHandlesAndMotionClearAnEarlierListAndCsv) {
  TempDir dir;
  const Scene scene = load_scene_file(dir.write("s.txt",
                                                "handle-vertices = 1,1\n"
                                                "trajectory = /x.csv\n"
                                                "handles = mid-edge\n"
                                                "motion = xyz_v3\n"));
  EXPECT_EQ(scene.handle_vertices, "");
  EXPECT_EQ(scene.trajectory, "");
  EXPECT_EQ(scene.handles, "mid-edge");
  EXPECT_EQ(scene.motion, "xyz_v3");
  Scene cleared;
  cleared.trajectory = "a.csv";
  apply_scene_setting(cleared, "trajectory", "");
  EXPECT_EQ(cleared.trajectory, "");
}

TEST(SceneFile, RoundTripsThroughToSceneText) {
  TempDir dir;
  Scene scene;
  scene.rows = 17;
  scene.cols = 9;
  scene.size = 0.1 + 0.2;  // not a short decimal: must survive exactly
  scene.grid_units_of = 32;
  scene.material.stretch = 1.0 / 3;
  scene.material.shear = 0.0;
  scene.material.bend = 1.2345678901234567e-5;
  scene.material.density = 0.187;
  scene.material.damping = 0.05;
  scene.handles = "corner-center";
  scene.handle_vertices = "0,0;16,8";
  scene.motion = "xyz_v4_opp";
  scene.trajectory = (dir.path() / "path.csv").string() + "#take";
  scene.speed = 1.2;
  scene.dt = 1.0 / 60;
  scene.frames = 123;
  scene.gravity = Vec3(0.1, -0.2, -9.80665);
  scene.repulsion = RepulsionMode::On;
  scene.material.repulsion_stiffness = 1.0 / 7;
  scene.material.repulsion_range = 0.8;
  resolve_repulsion(scene);
  const Scene loaded = load_scene_file(dir.write("round.txt", to_scene_text(scene)));
  expect_same_scene(loaded, scene);
  expect_same_scene(load_scene_file(dir.write("default.txt", to_scene_text(Scene()))), Scene());
}

TEST(SceneFile, RoundTripsAMaterialFile) {
  TempDir dir;
  Scene scene;
  scene.material_name = dir.write("knit.material", "stretch = 12\n");
  scene.material = material_preset(scene.material_name);
  scene.material.bend = 7e-6;  // an override on top of the file
  expect_same_scene(load_scene_file(dir.write("s.txt", to_scene_text(scene))), scene);
}

TEST(SceneFile, RepulsionModeRoundTripsForEveryPresetAndMode) {
  TempDir dir;
  for (const char* preset : {"corner", "diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center"})
    for (RepulsionMode mode : {RepulsionMode::Auto, RepulsionMode::On, RepulsionMode::Off}) {
      Scene scene;
      scene.handles = preset;
      scene.repulsion = mode;
      resolve_repulsion(scene);
      const std::string text = to_scene_text(scene);
      EXPECT_NE(text.find("repulsion = " + repulsion_mode_name(mode) +
                          "  # resolved: " + (repulsion_enabled(scene) ? "on" : "off")),
                std::string::npos)
          << text;
      const Scene loaded = load_scene_file(dir.write("r.txt", text));
      expect_same_scene(loaded, scene);
    }
}

TEST(SceneFile, RepulsionIsResolvedAfterEverySettingInAnyOrder) {
  TempDir dir;
  // auto, then a folding preset: on (without self-contact, which takes its place); then an explicit
  // list: off again; a later self-contact line decides too.
  EXPECT_TRUE(
      load_scene_file(dir.write("a.txt", "handles = single-mid-edge\nself-contact = off\n")).material.repulsion);
  EXPECT_FALSE(load_scene_file(dir.write("a2.txt", "handles = single-mid-edge\n")).material.repulsion);
  EXPECT_FALSE(load_scene_file(dir.write("b.txt", "self-contact = off\nhandles = corner-center\nhandle-vertices = 0,0\n"))
                   .material.repulsion);
  // A material line resets the material but not the decision.
  EXPECT_TRUE(load_scene_file(dir.write("c.txt", "repulsion = true\nmaterial = default\n")).material.repulsion);
  EXPECT_FALSE(load_scene_file(dir.write("d.txt", "handles = corner-center\nrepulsion = off\n")).material.repulsion);
  // A key given twice is a mistake, not an override: the file says where.
  const auto twice = dir.write("e.txt", "repulsion = on\nrepulsion = auto\n");
  EXPECT_TRUE(throws_error([&] { load_scene_file(twice); }, twice + ":2: repulsion: given twice (first on line 1)"));
}

// A scene file whose line `line` is bad fails with "<path>:<line>: <expected>".
void expect_line_error(const std::string& text, int line, const std::string& expected) {
  TempDir dir;
  const auto path = dir.write("bad.txt", text);
  EXPECT_TRUE(throws_error([&] { load_scene_file(path); }, path + ":" + std::to_string(line) + ": " + expected));
}

TEST(SceneFile, LineNumberedErrorsNameTheKey) {
  expect_line_error("res = 32\n\n# comment\ncolour = red\n", 4, "colour: unknown setting");
  expect_line_error("frames = ten\n", 1, "frames: expected an integer, got 'ten'");
  expect_line_error("size = 1\nframes = 0\n", 2, "frames: must be at least 1");
  expect_line_error("frames = 3.5\n", 1, "frames: expected an integer");
  expect_line_error("size = 1 m\n", 1, "size: expected a number, got '1 m'");
  expect_line_error("size = nan\n", 1, "size: must be a positive finite");
  expect_line_error("res = 2\n", 1, "res: the grid needs at least 3");
  expect_line_error("rows = 2\n", 1, "rows: ");
  expect_line_error("cols = -1\n", 1, "cols: ");
  expect_line_error("density = -0.187\n", 1, "density: ");
  expect_line_error("stretch = inf\n", 1, "stretch: ");
  expect_line_error("dt = 1/0\n", 1, "dt: ");
  expect_line_error("dt = 1/60/2\n", 1, "dt: expected a number or a fraction");
  expect_line_error("dt = -0.01\n", 1, "dt: must be a positive finite");
  expect_line_error("speed = 0\n", 1, "speed: ");
  expect_line_error("gravity = 0,-9.81\n", 1, "gravity: expected three numbers");
  expect_line_error("gravity = 0,0,nan\n", 1, "gravity: must be three finite numbers");
  expect_line_error("repulsion = maybe\n", 1, "repulsion: expected auto, true or false");
  expect_line_error("repulsion-stiffness = 0\n", 1, "repulsion-stiffness: ");
  expect_line_error("repulsion-range = -1\n", 1, "repulsion-range: ");
  expect_line_error("handles = corners\n", 1, "handles: unknown preset 'corners'");
  expect_line_error("handle-vertices = 1;2\n", 1, "handle-vertices: ");
  expect_line_error("motion = spin\n", 1, "motion: unknown motion 'spin'");
  expect_line_error("material = no-such-material\n", 1, "material: ");
  expect_line_error("size =\n", 1, "size: expected a value");
  expect_line_error("size 1.0\n", 1, "expected 'key = value', got 'size 1.0'");
  expect_line_error("= 1.0\n", 1, "missing key before '='");
}

TEST(SceneFile, RangeErrorsNeedingOtherFieldsComeFromValidate) {
  TempDir dir;
  const Scene scene = load_scene_file(dir.write("s.txt", "res = 8\nhandle-vertices = 0,8\n"));
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, "handle-vertices: vertex (0,8) is outside"));
}

TEST(SceneFile, RejectsUnreadableFiles) {
  TempDir dir;
  const auto missing = (dir.path() / "missing.txt").string();
  EXPECT_TRUE(throws_error([&] { load_scene_file(missing); }, "scene: cannot open '" + missing));
  EXPECT_TRUE(throws_error([&] { load_scene_file(dir.path().string()); }, "scene: cannot open"));
}

TEST(SceneSetting, AppliesOneSettingWithTheFileChecks) {
  Scene scene;
  apply_scene_setting(scene, "res", " 100 ");
  EXPECT_EQ(scene.rows, 100);
  EXPECT_EQ(scene.cols, 100);
  apply_scene_setting(scene, "speed", "1.5");
  EXPECT_EQ(scene.speed, 1.5);
  EXPECT_TRUE(throws_error([&] { apply_scene_setting(scene, "speed", "fast"); }, "speed: "));
  EXPECT_TRUE(throws_error([&] { apply_scene_setting(scene, "velocity", "1"); }, "velocity: unknown setting (valid: "));
}

}  // namespace
}  // namespace fnopt
