#include <fnopt/scenes/scene_settings.hpp>

#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

Scene apply_scene_settings(Scene base, const std::map<std::string, std::string>& settings,
                           const std::vector<Obstacle>& obstacles) {
  for (const auto& [key, value] : settings)
    require(find_scene_key(key) != nullptr, key, "unknown setting (valid: " + scene_key_names() + ")");
  for (const SceneKey& key : scene_keys()) {
    if (key.type == SceneKeyType::Obstacles)
      base.obstacles.insert(base.obstacles.end(), obstacles.begin(), obstacles.end());
    const auto setting = settings.find(key.name);
    if (setting == settings.end()) continue;
    // In a scene file an empty list clears an earlier one; given as a setting it is a mistake.
    require(!trim(setting->second).empty(), key.name, "is empty: give a value or leave the flag out");
    apply_scene_setting(base, key.name, setting->second);
  }
  resolve_repulsion(base);
  base.validate();
  return base;
}

}  // namespace fnopt
