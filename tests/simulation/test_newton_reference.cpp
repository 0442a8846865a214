// The Newton-reference cache: one name per scene, the same every time, another for any change.
#include <gtest/gtest.h>

#include <fnopt/simulation/newton_reference.hpp>

namespace fnopt {
namespace {

TEST(NewtonReference, TheCacheNameFollowsTheSceneAndNothingElse) {
  Scene scene;
  scene.rows = scene.cols = 16;
  const std::string path = newton_reference_path("dir", "16_xy_v2", scene);
  EXPECT_EQ(path.rfind("dir/newton_reference_16_xy_v2_", 0), 0u) << path;
  EXPECT_EQ(path, newton_reference_path("dir", "16_xy_v2", scene));
  Scene stiffer = scene;
  stiffer.material.stretch *= 2.0;
  Scene longer = scene;
  longer.frames += 1;
  EXPECT_NE(newton_reference_path("dir", "16_xy_v2", stiffer), path);
  EXPECT_NE(newton_reference_path("dir", "16_xy_v2", longer), path);
}

}  // namespace
}  // namespace fnopt
