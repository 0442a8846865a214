#pragma once
// A scene from named settings, as the command line's flags and the Python module's keyword
// arguments give them (docs/api.md): the keys of the scene file format (scene.hpp), applied in
// one fixed order whatever order they came in: the grid, the material preset, its overrides,
// then everything else, self-repulsion last. So `material` never undoes a `stretch` given with it.
#include <map>
#include <string>

#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// The settings on top of `base`, then validated. Throws Error("<key>", ...) for an unknown key,
// an empty value (given but blank) or a bad value, with the texts of the scene file's checks.
Scene apply_scene_settings(Scene base, const std::map<std::string, std::string>& settings);

}  // namespace fnopt
