#pragma once
// The one table of scene keys (docs/design.md §10): every setting a scene takes, with its name,
// type, unit, default, help text, check and where it is accepted. The scene file's parser and
// writer (scene.hpp), the order in which named settings apply (scene_settings.hpp), the command
// line's flags and their --help (app/scene_flags.cpp), the Python module's keywords, its `Scene`
// docstring and repr (python/src/scene.cpp) and the README's list (checked by a test) are all made
// from it, so a new key is one row here plus the field it sets.
#include <string>
#include <vector>

#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// What a key's value is, as text: how --help and the Python docstring describe it.
enum class SceneKeyType {
  Integer,
  Number,
  Text,       // a name, a list or a path
  Vector3,    // "x,y,z"
  Switch,     // auto, true or false (1/0, on/off); the command line has --KEY and --no-KEY
  Obstacles,  // obstacle specs (contact/obstacle_spec.hpp); repeatable, structured on every surface
};

// Where a key is accepted (a bit set).
enum SceneSurface : unsigned {
  kSceneFile = 1u,    // scene files, and rollout files' stored scenes
  kCommandLine = 2u,  // --KEY on every subcommand that builds a scene
  kPython = 4u,       // fnopt.Scene(KEYWORD=...)
  kEverySurface = kSceneFile | kCommandLine | kPython,
};

// How a key reads and writes its value.
struct SceneKeyCodec {
  // Parses `value` (trimmed), stores it and checks what it stored: Error("<key>", problem).
  void (*apply)(Scene& scene, const std::string& key, const std::string& value);
  // Appends the values this key writes to a scene file, one line each (none: the key is implied
  // by others or at a default that writes nothing).
  void (*write)(const Scene& scene, std::vector<std::string>& values);
  // A file's value with its relative paths taken relative to `directory` (nullptr: no paths).
  std::string (*rebase)(const std::string& directory, const std::string& value) = nullptr;
  // A switch's state once `auto` is decided (nullptr for other keys); the scene text notes it.
  bool (*resolved)(const Scene& scene) = nullptr;
};

enum SceneKeyOption : unsigned {
  kEmptyClears = 1u,  // an empty value clears the setting (a later file or flag undoes an earlier)
  kRepeatable = 2u,   // may stand on several lines of one file, each adding to it
};

struct SceneKey {
  const char* name;          // the scene file's key and the flag's name (--name)
  SceneKeyType type;
  const char* value_name;    // the value's placeholder in --help ("N", "X,Y,Z", "FILE")
  const char* unit;          // SI unit, "" if none
  const char* default_text;  // the default as a user reads it, "" where another key decides it
  const char* help;          // one line, without the unit and the default (help_text adds them)
  const char* example;       // a valid value (tests apply it on every surface)
  const char* excludes;      // keys the command line refuses together with this one, comma-separated
  unsigned surfaces;         // SceneSurface bits
  unsigned options;          // SceneKeyOption bits
  SceneKeyCodec codec;

  bool empty_clears() const { return (options & kEmptyClears) != 0; }
  bool repeatable() const { return (options & kRepeatable) != 0; }
  bool accepted_by(SceneSurface surface) const { return (surfaces & surface) != 0; }
  // The Python keyword: the name with '_' for '-' ("handle_vertices"); "obstacles" for obstacle.
  std::string python_keyword() const;
  // The help line with its unit and default: "side of the cloth's longer edge [m] (default 1)".
  std::string help_text() const;
};

// Every key, in the order settings apply and the scene file is written: the grid, the material
// preset, then its overrides (so `material` never undoes a `stretch` given with it), then the rest.
const std::vector<SceneKey>& scene_keys();
// The key of that name, or nullptr.
const SceneKey* find_scene_key(const std::string& name);
// The key a Python keyword names ("handle_vertices", "obstacles"), or nullptr.
const SceneKey* find_scene_keyword(const std::string& keyword);
// The key's "name = value" lines of the scene's file text, with a switch's resolved state as a comment.
std::vector<std::string> scene_file_lines(const SceneKey& key, const Scene& scene);
// Every key's name, comma-separated (error messages).
std::string scene_key_names();
// The type as the docs name it: "int", "float", "str", "x,y,z", "auto|true|false", "obstacle specs".
const char* to_string(SceneKeyType type);

}  // namespace fnopt
