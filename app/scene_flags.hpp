#pragma once
// The scene flags shared by simulate, compare, stability, bench: each flag is a scene-file key
// (scenes/scene.hpp), applied after --scene FILE, so flags override the file.
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include <fnopt/scenes/scene.hpp>

namespace fnopt::app {

class SceneFlags {
 public:
  // Adds --scene, --res, --rows, --cols, --size, --handles, --handle-vertices, --motion,
  // --trajectory, --speed, --frames, --dt, --material, --stretch, --shear, --bend, --density,
  // --damping, --gravity, --repulsion-stiffness, --repulsion-range, --placement, --let-go,
  // --contact-stiffness, --contact-range, --contact-thickness, --obstacle (repeatable; the specs go
  // to the scene's obstacle setting, after any of the --scene file), --repulsion / --no-repulsion
  // (self-repulsion on / off; neither: auto, see repulsion_enabled). `with_resolution` false leaves out
  // --res/--rows/--cols (for commands that take a list of resolutions).
  void add_to(CLI::App& command, bool with_resolution = true);
  // The scene: defaults, then the --scene file, then every flag given (in a fixed order:
  // grid, material, then the material overrides, then the rest).
  Scene scene() const;
  // A command's own defaults where neither a flag nor --scene sets them: the grid (N x N), the
  // steps and the handles' speed. --frames counts the steps after the initial frame, which is
  // added, as `fnopt simulate` runs them. Validated and resolved.
  ResolvedScene scene_of_steps(int resolution, int steps, double speed) const;

 private:
  std::string scene_file_;
  std::map<std::string, std::string> values_;
  std::map<std::string, CLI::Option*> options_;
  std::vector<std::string> obstacles_;  // --obstacle, one spec each
  bool repulsion_ = false;
  CLI::Option* repulsion_flag_ = nullptr;
  bool no_repulsion_ = false;
  CLI::Option* no_repulsion_flag_ = nullptr;
};

}  // namespace fnopt::app
