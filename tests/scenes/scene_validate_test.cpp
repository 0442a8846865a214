// Every invalid scene value is rejected with one line naming its field.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "scenes/scene.hpp"
#include "tests/boundary/error_message.hpp"

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

TEST(SceneValidate, TheDefaultSceneIsValid) {
  EXPECT_NO_THROW(Scene().validate());
}

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
    for (int axis = 0; axis < 3; ++axis)
      expect_invalid([&](Scene& s) { s.gravity[axis] = bad; }, "gravity: ");
    expect_invalid([&](Scene& s) { s.material.stretch = bad; }, "stretch: ");
    expect_invalid([&](Scene& s) { s.material.shear = bad; }, "shear: ");
    expect_invalid([&](Scene& s) { s.material.bend = bad; }, "bend: ");
    expect_invalid([&](Scene& s) { s.material.density = bad; }, "density: ");
    expect_invalid([&](Scene& s) { s.material.damping = bad; }, "damping: ");
  }
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
