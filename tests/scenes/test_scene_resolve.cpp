// resolve(): the grid, handles and trajectory a scene names.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

using testing::TempDir;
using testing::throws_error;

void expect_near(const Vec3& actual, const Vec3& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-12)
      << "actual (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

TEST(SceneResolve, TheDefaultSceneIsTheBenchmark) {
  const ResolvedScene setup = resolve(Scene());
  EXPECT_EQ(setup.grid.rows, 32);
  EXPECT_EQ(setup.grid.cols, 32);
  EXPECT_DOUBLE_EQ(setup.grid.spacing, 1.0 / 31);
  EXPECT_EQ(setup.handles.name, "corner");
  EXPECT_EQ(setup.handles.vertices, (std::vector<int>{0, 31}));
  ASSERT_EQ(setup.trajectory->handle_count(), 2);
  const Vec3 half_way = 0.5 * Vec3(1, 1, 0) / std::sqrt(2.0);  // xy_v2 at t = 1.0
  expect_near(setup.trajectory->position(0, 1.0), Vec3(0, 0, 0) + half_way);
  expect_near(setup.trajectory->position(1, 1.0), Vec3(1, 0, 0) + half_way);
}

// The paper's protocol: a 100^2 scene held in the grid units of 32^2 is, step for step, as stiff
// in grid units as the 32^2 scene; the resolved scene holds physical values and no key, so
// resolving it again changes nothing.
TEST(SceneResolve, GridUnitsOfHoldsTheGridUnitNumbersOfThatGrid) {
  auto grid_units = [](const ResolvedScene& r) {
    return grid_unit_stiffness(r.grid, r.scene.material, r.scene.dt, r.scene.gravity.norm());
  };
  for (const char* extent : {"100", "64"}) {
    const ResolvedScene coarse = resolve(apply_scene_settings({}, {{"res", "32"}, {"stretch", "80"}}));
    const ResolvedScene held =
        resolve(apply_scene_settings({}, {{"res", extent}, {"stretch", "80"}, {"grid-units-of", "32"}}));
    const GridUnitStiffness want = grid_units(coarse), got = grid_units(held);
    EXPECT_NEAR(got.stretch, want.stretch, 1e-12 * want.stretch) << extent;
    EXPECT_NEAR(got.shear, want.shear, 1e-12 * want.shear) << extent;
    EXPECT_NEAR(got.bend, want.bend, 1e-12 * want.bend) << extent;
    EXPECT_NEAR(got.gravity, want.gravity, 1e-12 * want.gravity) << extent;
    EXPECT_EQ(held.scene.gravity.normalized(), coarse.scene.gravity.normalized());
    EXPECT_EQ(held.scene.material.density, coarse.scene.material.density);
    EXPECT_EQ(held.scene.material.damping, coarse.scene.material.damping);
    EXPECT_EQ(held.scene.grid_units_of, 0);
    EXPECT_EQ(resolve(held.scene).scene.material.stretch, held.scene.material.stretch);
  }
  // Held at its own grid, or not held: the physical scene.
  const Scene own = apply_scene_settings({}, {{"res", "64"}, {"grid-units-of", "64"}});
  EXPECT_EQ(resolve(own).scene.material.stretch, Scene().material.stretch);
  EXPECT_EQ(resolve(own).scene.gravity, Scene().gravity);
  EXPECT_TRUE(throws_error(
      [] {
        apply_scene_settings({}, {{"grid-units-of", "2"}});
      },
      "grid-units-of: the grid needs"));
  Scene negative;
  negative.grid_units_of = -5;
  EXPECT_TRUE(throws_error([&] { resolve(negative); }, "grid-units-of: must be 0 (off)"));
}

TEST(SceneResolve, MotionsStartAtTheHandlesRestPositions) {
  Scene scene;
  scene.rows = scene.cols = 5;
  scene.size = 2.0;
  scene.handles = "mid-edge";  // (2,0) and (2,4): rest (0,0,-1) and (2,0,-1)
  scene.motion = "rot_h0";
  const ResolvedScene setup = resolve(scene);
  EXPECT_EQ(setup.handles.vertices, (std::vector<int>{10, 14}));
  expect_near(setup.trajectory->position(0, 0.0), Vec3(0, 0, -1));
  expect_near(setup.trajectory->position(1, 0.0), Vec3(2, 0, -1));
  expect_near(setup.trajectory->position(1, 3.5), Vec3(0, 2, -1));  // a quarter turn
}

TEST(SceneResolve, AnExplicitListBeatsThePreset) {
  Scene scene;
  scene.handle_vertices = "31,31;0,0;5,7";
  scene.motion = "static";
  const ResolvedScene setup = resolve(scene);
  EXPECT_EQ(setup.handles.name, "vertices");
  EXPECT_EQ(setup.handles.vertices, (std::vector<int>{31 * 32 + 31, 0, 5 * 32 + 7}));
  ASSERT_EQ(setup.trajectory->handle_count(), 3);
  expect_near(setup.trajectory->position(0, 2.0), Vec3(1, 0, -1));
}

TEST(SceneResolve, ATrajectoryCsvBeatsTheMotionAndSpeedApplies) {
  TempDir dir;
  Scene scene;
  scene.trajectory = dir.write("path.csv",
                               "t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z\n"
                               "0,0,0,0,1,0,0\n"
                               "2,0,0,2,1,0,2\n");
  scene.speed = 2.0;
  const ResolvedScene setup = resolve(scene);
  expect_near(setup.trajectory->position(0, 0.5), Vec3(0, 0, 1));
  expect_near(setup.trajectory->position(1, 0.5), Vec3(1, 0, 1));
}

TEST(SceneResolve, RejectsUnreadableAndNonMonotonicCsvs) {
  TempDir dir;
  Scene scene;
  scene.trajectory = (dir.path() / "missing.csv").string();
  EXPECT_TRUE(throws_error([&] { resolve(scene); }, "trajectory: " + scene.trajectory));
  scene.trajectory = dir.write("back.csv",
                               "t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z\n"
                               "0,0,0,0,1,0,0\n"
                               "1,0,0,0,1,0,0\n"
                               "0.5,0,0,0,1,0,0\n");
  EXPECT_TRUE(
      throws_error([&] { resolve(scene); }, "trajectory: " + scene.trajectory + ": line 4: time t_s = 0.5 does not"));
}

TEST(SceneResolve, RejectsACsvForAnotherHandleCount) {
  TempDir dir;
  Scene scene;
  scene.handles = "single-center";
  scene.trajectory = dir.write("two.csv", "t_s,h0_x,h0_y,h0_z,h1_x,h1_y,h1_z\n0,0,0,0,1,0,0\n");
  EXPECT_TRUE(throws_error([&] { resolve(scene); }, "trajectory: "));
  scene.handles = "corner";
  scene.trajectory = dir.write("one.csv", "t_s,h0_x,h0_y,h0_z\n0,0,0,0\n");
  EXPECT_TRUE(throws_error([&] { resolve(scene); }, "missing column 'h1_x'"));
}

TEST(SceneResolve, SelfContactAutoIsOnWhereTheClothCanFold) {
  const std::map<std::string, bool> folds = {{"corner", false},         {"diagonal", false},
                                             {"mid-edge", false},       {"corner-center", true},
                                             {"single-mid-edge", true}, {"single-center", false},
                                             {"none", true}};
  for (const auto& [preset, auto_on] : folds) {
    Scene scene;
    scene.handles = preset;
    EXPECT_EQ(scene.self_contact, AutoSwitch::Auto);  // the default
    EXPECT_EQ(self_contact_enabled(scene), auto_on) << preset;
    EXPECT_EQ(self_contact_of(scene).has_value(), auto_on) << preset;
    scene.let_go = 0.5;  // a released cloth
    EXPECT_TRUE(self_contact_enabled(scene)) << preset;
    scene.let_go = -1.0;
    apply_scene_setting(scene, "obstacle", "plane point=0,0,-5 normal=0,0,1");
    EXPECT_TRUE(self_contact_enabled(scene)) << preset;
    scene.self_contact = AutoSwitch::Off;
    EXPECT_FALSE(self_contact_enabled(scene)) << preset;
  }
  // The paper's benchmark: off, and its scene text as before self-contact.
  EXPECT_FALSE(self_contact_enabled(Scene{}));
  EXPECT_EQ(to_scene_text(Scene{}).find("self-contact"), std::string::npos);
}

// Self-contact takes self-repulsion's place: with self-contact off, repulsion's auto is on exactly
// for the folding presets; with self-contact on (its auto there), off.
TEST(SceneResolve, RepulsionAutoIsOnExactlyForTheFoldingPresetsWithoutSelfContact) {
  const std::map<std::string, bool> folds = {{"corner", false},         {"diagonal", false},
                                             {"mid-edge", false},       {"corner-center", true},
                                             {"single-mid-edge", true}, {"single-center", false}};
  for (const auto& [preset, auto_on] : folds) {
    Scene with_self_contact;
    with_self_contact.handles = preset;
    EXPECT_FALSE(repulsion_enabled(with_self_contact)) << preset;
    Scene scene;
    scene.self_contact = AutoSwitch::Off;
    scene.handles = preset;
    EXPECT_EQ(scene.repulsion, RepulsionMode::Auto);  // the default
    EXPECT_EQ(repulsion_enabled(scene), auto_on) << preset;
    scene.repulsion = RepulsionMode::On;
    EXPECT_TRUE(repulsion_enabled(scene)) << preset;
    scene.repulsion = RepulsionMode::Off;
    EXPECT_FALSE(repulsion_enabled(scene)) << preset;
    // Settings resolve it into the material the objective reads.
    Scene set;
    apply_scene_setting(set, "self-contact", "false");
    apply_scene_setting(set, "handles", preset);
    EXPECT_EQ(set.material.repulsion, auto_on) << preset;
    apply_scene_setting(set, "repulsion", "true");
    EXPECT_TRUE(set.material.repulsion);
    apply_scene_setting(set, "repulsion", "false");
    EXPECT_FALSE(set.material.repulsion);
    apply_scene_setting(set, "repulsion", "auto");
    EXPECT_EQ(set.material.repulsion, auto_on) << preset;
  }
  // An explicit vertex list is not a preset: auto leaves repulsion off.
  Scene listed;
  listed.self_contact = AutoSwitch::Off;
  listed.handles = "corner-center";
  listed.handle_vertices = "0,0;16,16";
  EXPECT_FALSE(repulsion_enabled(listed));
  Scene scene;
  scene.self_contact = AutoSwitch::Off;
  scene.handles = "single-mid-edge";
  EXPECT_FALSE(scene.material.repulsion);  // set directly: not resolved until asked
  resolve_repulsion(scene);
  EXPECT_TRUE(scene.material.repulsion);
}

}  // namespace
}  // namespace fnopt
