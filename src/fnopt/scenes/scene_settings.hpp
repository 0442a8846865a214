#pragma once
// A scene from named settings, as the command line's flags and the Python module's keyword
// arguments give them (docs/api.md): the keys of the scene key table (scene_keys.hpp), applied in
// the table's order whatever order they came in, so `material` never undoes a `stretch` given
// with it. Obstacles come as values, each parsed once where the user wrote it.
#include <map>
#include <string>
#include <vector>

#include <fnopt/contact/obstacle.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// The settings on top of `base`, then `obstacles` added after the base's, then validated. Throws
// Error("<key>", ...) for an unknown key, an empty value (given but blank) or a bad value, with
// the texts of the scene file's checks.
Scene apply_scene_settings(Scene base, const std::map<std::string, std::string>& settings,
                           const std::vector<Obstacle>& obstacles = {});

}  // namespace fnopt
