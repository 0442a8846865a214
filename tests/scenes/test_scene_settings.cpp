// Named settings, as flags and Python keywords give them: applied in one fixed order whatever
// order they came in, refused when empty, and validated at the end.
#include <gtest/gtest.h>

#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TEST(SceneSettings, TheMaterialPresetNeverUndoesAnOverrideGivenWithIt) {
  // "material" sorts after "bend" and "stretch" by name; it applies before them by rule.
  const Scene scene = apply_scene_settings({}, {{"stretch", "123"}, {"bend", "1e-4"}, {"material", "default"}});
  EXPECT_EQ(scene.material.stretch, 123.0);
  EXPECT_EQ(scene.material.bend, 1e-4);
}

TEST(SceneSettings, TheGridComesBeforeTheHandlesThatMustFitOnIt) {
  const Scene scene = apply_scene_settings({}, {{"handle-vertices", "0,0;0,39"}, {"res", "40"}});
  EXPECT_EQ(scene.cols, 40);
  EXPECT_EQ(scene.handle_vertices, "0,0;0,39");
}

TEST(SceneSettings, EmptyUnknownAndInvalidSettingsAreRefusedByName) {
  try {
    apply_scene_settings({}, {{"motion", "  "}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "motion");
    EXPECT_EQ(e.problem(), "is empty: give a value or leave the flag out");
  }
  try {
    apply_scene_settings({}, {{"colour", "red"}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "colour");
  }
  try {
    apply_scene_settings({}, {{"frames", "0"}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "frames");
  }
}

}  // namespace
}  // namespace fnopt
