// The table of scene keys: every key reads its example on every surface, writes it back into the
// scene file's text, and is listed where users look for it (README, --help, the Python docstring:
// tests/app/test_cli.cpp and python/tests/test_scene.py).
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

TEST(SceneKeys, NamesAndKeywordsAreUniqueAndEveryKeyIsDocumented) {
  std::set<std::string> names, keywords;
  for (const SceneKey& key : scene_keys()) {
    EXPECT_TRUE(names.insert(key.name).second) << key.name;
    EXPECT_TRUE(keywords.insert(key.python_keyword()).second) << key.name;
    EXPECT_NE(std::string(key.help), "") << key.name;
    EXPECT_NE(std::string(key.example), "") << key.name;
    EXPECT_NE(std::string(key.value_name), "") << key.name;
    EXPECT_EQ(find_scene_key(key.name), &key);
    EXPECT_EQ(find_scene_keyword(key.python_keyword()), &key);
    for (const std::string_view other : split(key.excludes, ','))
      if (!other.empty()) {
        EXPECT_NE(find_scene_key(std::string(other)), nullptr) << key.name << " excludes " << other;
      }
  }
  EXPECT_EQ(find_scene_key("colour"), nullptr);
}

// A scene with an obstacle far away, so that every key, the contact settings too, is written.
Scene scene_with_an_obstacle() {
  Scene scene;
  apply_scene_setting(scene, "obstacle", "plane point=0,0,-5 normal=0,0,1");
  return scene;
}

// Every key's example (where it is not the default) changes the scene, the change is written to
// the scene's text (but for res, which rows and cols write), and the text reads back to the same
// scene.
TEST(SceneKeys, EveryExampleAppliesAndRoundTripsThroughTheSceneText) {
  const std::string defaults = to_scene_text(scene_with_an_obstacle());
  for (const SceneKey& key : scene_keys()) {
    SCOPED_TRACE(key.name);
    Scene scene = scene_with_an_obstacle();
    ASSERT_NO_THROW(apply_scene_setting(scene, key.name, key.example));
    ASSERT_NO_THROW(scene.validate());
    const std::string text = to_scene_text(scene);
    if (std::string(key.example) != key.default_text) {
      EXPECT_NE(text, defaults);
    }
    if (std::string(key.name) != "res") {
      EXPECT_NE(text.find(std::string(key.name) + " = "), std::string::npos) << text;
    }
    EXPECT_EQ(to_scene_text(load_scene_text(text, "written")), text);
  }
}

TEST(SceneKeys, EveryKeyAppliesAsANamedSettingInTheTablesOrder) {
  for (const SceneKey& key : scene_keys()) {
    SCOPED_TRACE(key.name);
    Scene one;
    apply_scene_setting(one, key.name, key.example);
    EXPECT_EQ(to_scene_text(apply_scene_settings({}, {{key.name, key.example}})), to_scene_text(one));
  }
}

TEST(SceneKeys, HelpTextsCarryTheUnitAndTheDefault) {
  const SceneKey& size = *find_scene_key("size");
  EXPECT_EQ(size.help_text(), "side of the cloth's longer edge [m] (default 1)");
  EXPECT_EQ(find_scene_key("handle-vertices")->help_text(), "explicit handle vertices (overrides handles)");
}

TEST(SceneKeys, TheSceneFileRefusesASecondLineOfAKeyThatIsNotRepeatable) {
  try {
    load_scene_text("speed = 1\nspeed = 2\n", "s.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "s.txt:2: speed: given twice (first on line 1)");
  }
  const Scene two = load_scene_text(
      "obstacle = sphere center=0.5,-1,-1 radius=0.1\nobstacle = plane point=0,0,-2 normal=0,0,1\n", "s.txt");
  EXPECT_EQ(two.obstacles.size(), 2u);
}

// The README's list of scene flags names every key the command line takes (a switch with its
// --no- form).
TEST(SceneKeys, TheReadmeListsEveryCommandLineKey) {
  std::ifstream in(std::string(FNOPT_SOURCE_DIR) + "/README.md");
  ASSERT_TRUE(in);
  std::stringstream readme;
  readme << in.rdbuf();
  const auto names = [&](const std::string& flag) {
    return std::regex_search(readme.str(), std::regex(flag + "(?![a-z-])"));
  };
  for (const SceneKey& key : scene_keys()) {
    if (!key.accepted_by(kCommandLine)) continue;
    EXPECT_TRUE(names("--" + std::string(key.name))) << key.name;
    if (key.type == SceneKeyType::Switch) {
      EXPECT_TRUE(names("--no-" + std::string(key.name))) << key.name;
    }
  }
}

}  // namespace
}  // namespace fnopt
