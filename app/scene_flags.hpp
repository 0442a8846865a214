#pragma once
// The scene flags shared by simulate, compare, stability, bench and the others: one flag per key of
// the scene key table (scenes/scene_keys.hpp) that the command line takes, applied after
// --scene FILE, so flags override the file.
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include <fnopt/scenes/scene.hpp>

namespace fnopt::app {

class SceneFlags {
 public:
  // Adds --scene and a flag per command-line key: --KEY VALUE, --KEY and --no-KEY for a switch
  // (neither: auto), --obstacle SPEC repeatable (added after the --scene file's). Pairs that set
  // one thing two ways are refused together. `with_resolution` false leaves out --res/--rows/--cols
  // (for commands that take a list of resolutions).
  void add_to(CLI::App& command, bool with_resolution = true);
  // The scene: defaults, then the --scene file, then every flag given, in the table's order.
  Scene scene() const;
  // A command's own defaults where neither a flag nor --scene sets them: the grid (N x N), the
  // steps and the handles' speed. --frames counts the steps after the initial frame, which is
  // added, as `fnopt simulate` runs them. Validated and resolved.
  ResolvedScene scene_of_steps(int resolution, int steps, double speed) const;

 private:
  bool given(const std::string& key) const;

  std::string scene_file_;
  std::map<std::string, std::string> values_;
  std::map<std::string, CLI::Option*> options_;
  std::map<std::string, CLI::Option*> negations_;  // --no-KEY of each switch
  std::vector<std::string> obstacles_;             // --obstacle, one spec each
};

}  // namespace fnopt::app
