#include "app/scene_flags.hpp"

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt::app {
namespace {

bool is_resolution(const std::string& key) { return key == "res" || key == "rows" || key == "cols"; }

}  // namespace

void SceneFlags::add_to(CLI::App& command, bool with_resolution) {
  command.add_option("--scene", scene_file_, "scene file (key = value lines); flags override it")
      ->check(CLI::ExistingFile);
  for (const SceneKey& key : scene_keys()) {
    const std::string name = key.name;
    if (!key.accepted_by(kCommandLine) || (!with_resolution && is_resolution(name))) continue;
    if (key.type == SceneKeyType::Switch) {
      options_[name] = command.add_flag("--" + name)->description("turn on " + key.help_text());
      negations_[name] = command.add_flag("--no-" + name)->description("turn off " + std::string(key.help));
      options_[name]->excludes(negations_[name]);
    } else if (key.type == SceneKeyType::Obstacles) {
      options_[name] = command.add_option("--" + name, obstacles_, key.help_text())->type_name(key.value_name);
    } else {
      options_[name] = command.add_option("--" + name, values_[name], key.help_text())->type_name(key.value_name);
    }
  }
  // Flags that set the same thing two ways are refused together rather than one silently winning.
  for (const SceneKey& key : scene_keys())
    for (const std::string_view other : split(key.excludes, ','))
      if (options_.count(key.name) && options_.count(std::string(other)))
        options_[key.name]->excludes(options_[std::string(other)]);
}

bool SceneFlags::given(const std::string& key) const {
  return (options_.count(key) && options_.at(key)->count() > 0) ||
         (negations_.count(key) && negations_.at(key)->count() > 0);
}

ResolvedScene SceneFlags::scene_of_steps(int resolution, int steps, double speed) const {
  Scene scene = this->scene();
  if (scene_file_.empty()) {
    if (!given("res") && !given("rows") && !given("cols")) scene.rows = scene.cols = resolution;
    if (!given("frames")) scene.frames = steps;
    if (!given("speed")) scene.speed = speed;
  }
  scene.frames += 1;
  scene.validate();
  return resolve(scene);
}

Scene SceneFlags::scene() const {
  const Scene base = scene_file_.empty() ? Scene{} : load_scene_file(scene_file_);
  std::map<std::string, std::string> settings;
  for (const SceneKey& key : scene_keys()) {
    if (!given(key.name) || key.type == SceneKeyType::Obstacles) continue;
    if (key.type == SceneKeyType::Switch)
      settings[key.name] = options_.at(key.name)->count() > 0 ? "true" : "false";
    else
      settings[key.name] = values_.at(key.name);
  }
  std::vector<Obstacle> obstacles;
  for (const std::string& spec : obstacles_) obstacles.push_back(parse_obstacle(spec));
  return apply_scene_settings(base, settings, obstacles);
}

}  // namespace fnopt::app
