// Every invalid scene value is rejected with one line naming its field.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include <fnopt/scenes/scene.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using testing::throws_error;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// The default scene with one change must fail validate() with a message containing `expected`.
void expect_invalid(const std::function<void(Scene&)>& change, const std::string& expected) {
  Scene scene;
  change(scene);
  EXPECT_TRUE(throws_error([&] { scene.validate(); }, expected));
  EXPECT_TRUE(throws_error([&] { resolve(scene); }, expected));
}

TEST(SceneValidate, TheDefaultSceneIsValid) { EXPECT_NO_THROW(Scene().validate()); }

TEST(SceneValidate, RejectsGridsSmallerThan3x3) {
  expect_invalid([](Scene& s) { s.rows = s.cols = 2; }, "rows: ");
  expect_invalid([](Scene& s) { s.cols = 2; }, "cols: ");
  expect_invalid([](Scene& s) { s.rows = -4; }, "rows: ");
}

TEST(SceneValidate, RejectsBadSizeTimeStepFramesAndSpeed) {
  expect_invalid([](Scene& s) { s.size = 0.0; }, "size: ");
  expect_invalid([](Scene& s) { s.size = -1.0; }, "size: ");
  expect_invalid([](Scene& s) { s.dt = 0.0; }, "dt: ");
  expect_invalid([](Scene& s) { s.dt = -0.01; }, "dt: ");
  expect_invalid([](Scene& s) { s.frames = 0; }, "frames: ");
  expect_invalid([](Scene& s) { s.frames = -3; }, "frames: ");
  expect_invalid([](Scene& s) { s.speed = 0.0; }, "speed: ");
  expect_invalid([](Scene& s) { s.speed = -1.5; }, "speed: ");
}

TEST(SceneValidate, RejectsNaNAndInfinityInEveryRealField) {
  for (double bad : {kNaN, kInf, -kInf}) {
    expect_invalid([&](Scene& s) { s.size = bad; }, "size: ");
    expect_invalid([&](Scene& s) { s.dt = bad; }, "dt: ");
    expect_invalid([&](Scene& s) { s.speed = bad; }, "speed: ");
    for (int axis = 0; axis < 3; ++axis) expect_invalid([&](Scene& s) { s.gravity[axis] = bad; }, "gravity: ");
    expect_invalid([&](Scene& s) { s.material.stretch = bad; }, "stretch: ");
    expect_invalid([&](Scene& s) { s.material.shear = bad; }, "shear: ");
    expect_invalid([&](Scene& s) { s.material.bend = bad; }, "bend: ");
    expect_invalid([&](Scene& s) { s.material.density = bad; }, "density: ");
    expect_invalid([&](Scene& s) { s.material.damping = bad; }, "damping: ");
  }
}

// Every value finite, but a grid unit (docs/design.md §2) out of range: refused before work,
// naming the field, not a rollout that diverges at step 1.
TEST(SceneValidate, RejectsScenesWhoseGridUnitsOverflow) {
  expect_invalid([](Scene& s) { s.material.stretch = 1e300; }, "stretch: 1e+300 N/m overflows in grid units");
  expect_invalid([](Scene& s) { s.material.shear = 1e300; }, "shear: 1e+300 N/m overflows in grid units");
  expect_invalid([](Scene& s) { s.material.bend = 1e305; }, "bend: 1e+305 N m overflows in grid units");
  expect_invalid([](Scene& s) { s.gravity = Vec3(0, 0, -1e307); }, "gravity: ");
  expect_invalid(
      [](Scene& s) {
        s.material.damping = 1e307;
        s.dt = 100.0;
      },
      "damping: ");
  expect_invalid([](Scene& s) { s.material.repulsion_stiffness = 1e300; }, "repulsion-stiffness: ");
  // The scales themselves: a step too long or too short to square, a vertex mass or a cell too
  // small to represent.
  expect_invalid([](Scene& s) { s.dt = 1e200; }, "dt: 1e+200 s is out of range in grid units");
  expect_invalid([](Scene& s) { s.dt = 1e-170; }, "dt: ");
  expect_invalid([](Scene& s) { s.material.density = 1e-320; }, "density: ");
  expect_invalid([](Scene& s) { s.size = 1e-80; }, "size: ");
  // Stiff but representable scenes stay valid (the stability suite runs stretch x1000).
  Scene stiff;
  stiff.material.stretch *= 1000.0;
  stiff.rows = stiff.cols = 200;
  EXPECT_NO_THROW(stiff.validate());
}

TEST(SceneValidate, RejectsNegativeMaterialValues) {
  expect_invalid([](Scene& s) { s.material.density = -0.187; }, "density: ");
  expect_invalid([](Scene& s) { s.material.stretch = -1.0; }, "stretch: ");
  expect_invalid([](Scene& s) { s.material.bend = -1e-5; }, "bend: ");
}

TEST(SceneValidate, RejectsUnknownPresetAndMotionNames) {
  expect_invalid([](Scene& s) { s.handles = "corners"; }, "handles: unknown preset 'corners'");
  expect_invalid([](Scene& s) { s.motion = "spin"; }, "motion: unknown motion 'spin'");
  // Checked even when an explicit list or a CSV makes them unused.
  expect_invalid([](Scene& s) { s.handles = "x", s.handle_vertices = "0,0"; }, "handles: ");
  expect_invalid([](Scene& s) { s.motion = "x", s.trajectory = "t.csv"; }, "motion: ");
}

TEST(SceneValidate, RejectsHandleVerticesOffTheGridOrMalformed) {
  expect_invalid([](Scene& s) { s.handle_vertices = "0,32"; }, "handle-vertices: vertex (0,32)");
  expect_invalid([](Scene& s) { s.rows = 5, s.handle_vertices = "5,0"; }, "handle-vertices: ");
  expect_invalid([](Scene& s) { s.handle_vertices = "0;0"; }, "handle-vertices: ");
  expect_invalid([](Scene& s) { s.handle_vertices = "0,0;0,0"; }, "handle-vertices: ");
}

TEST(SceneValidate, RejectsRotH1WithOneHandle) {
  expect_invalid([](Scene& s) { s.handles = "single-center", s.motion = "rot_h1"; }, "motion: ");
  expect_invalid([](Scene& s) { s.handle_vertices = "3,3", s.motion = "rot_h1_opp"; }, "motion: ");
  Scene scene;
  scene.handles = "single-center";
  scene.motion = "rot_h0";
  EXPECT_NO_THROW(scene.validate());
}

}  // namespace
}  // namespace fnopt
