#include "app/scene_flags.hpp"

#include <fnopt/scenes/scene_settings.hpp>

namespace fnopt::app {
namespace {

struct FlagSpec {
  const char* key;
  const char* help;
};

// In the order of --help; they apply in apply_scene_settings's order (scenes/scene_settings.hpp).
const FlagSpec kFlags[] = {
    {"res", "grid resolution N (N x N vertices)"},
    {"rows", "grid rows R (non-square grids)"},
    {"cols", "grid columns C (non-square grids)"},
    {"size", "side of the cloth's longer edge [m] (default 1)"},
    {"grid-units-of",
     "N0: hold the material's grid-unit stiffness and gravity at this scene's on an N0 x N0 grid, at any "
     "resolution (the FNOpt paper's protocol; docs/design.md §2); default: one physical cloth"},
    {"material", "material preset ('default') or a material file from fit-material"},
    {"stretch", "stretch stiffness k_s [N/m]"},
    {"shear", "shear stiffness k_sh [N/m]"},
    {"bend", "bending stiffness k_b [N m]"},
    {"density", "area density rho [kg/m^2]"},
    {"damping", "damping coefficient c [1/s]"},
    {"handles", "handle preset: corner, diagonal, mid-edge, corner-center, single-mid-edge, single-center, none"},
    {"handle-vertices", "explicit handle vertices 'i,j;i,j;...' (overrides --handles)"},
    {"motion", "handle motion: xy_v2, ..., rot_h1_opp, static"},
    {"trajectory", "CSV of handle positions (t_s, hK_x, hK_y, hK_z); FILE.csv#MOTION picks rows"},
    {"speed", "handle speed factor alpha"},
    {"frames", "number of time steps"},
    {"dt", "time step [s] (default 1/60)"},
    {"gravity", "gravity vector 'x,y,z' [m/s^2]"},
    {"repulsion-stiffness", "self-repulsion barrier stiffness lambda [N/m] (default 10)"},
    {"repulsion-range", "self-repulsion range delta in cell widths h (default 1)"},
    {"placement",
     "the cloth at rest: vertical (hanging in the x-z plane, the default) or horizontal (in the x-y plane "
     "at z = 0, centred on the z axis)"},
    {"let-go", "release every handle at this time [s] (default: never)"},
    {"contact-stiffness", "obstacle barrier stiffness kappa [N/m] (default 10; docs/design.md §14)"},
    {"contact-range", "obstacle barrier range dhat in cell widths h (default 0.5)"},
    {"contact-thickness", "the gap the barrier keeps from every obstacle [m] (default 0.001)"},
};

}  // namespace

void SceneFlags::add_to(CLI::App& command, bool with_resolution) {
  command.add_option("--scene", scene_file_, "scene file (key = value lines); flags override it")
      ->check(CLI::ExistingFile);
  for (const FlagSpec& flag : kFlags) {
    const std::string key = flag.key;
    if (!with_resolution && (key == "res" || key == "rows" || key == "cols")) continue;
    options_[key] = command.add_option("--" + key, values_[key], flag.help);
  }
  command.add_option("--obstacle", obstacles_,
                     "an obstacle, repeatable: 'sphere center=X,Y,Z radius=R', 'plane point=X,Y,Z normal=X,Y,Z', "
                     "'box center=X,Y,Z size=SX,SY,SZ rounding=R' or 'capsule a=X,Y,Z b=X,Y,Z radius=R', each with "
                     "optional friction=MU and motion=NAME or path=FILE.csv (docs/design.md §14)");
  repulsion_flag_ = command.add_flag(
      "--repulsion", repulsion_,
      "enable self-repulsion (default: auto, on for the folding presets corner-center and single-mid-edge)");
  no_repulsion_flag_ = command.add_flag("--no-repulsion", no_repulsion_, "disable self-repulsion");
  repulsion_flag_->excludes(no_repulsion_flag_);
  // Flags that set the same thing two ways are refused together rather than one silently winning.
  auto exclusive = [&](const char* a, const char* b) {
    if (options_.count(a) && options_.count(b)) options_[a]->excludes(options_[b]);
  };
  exclusive("res", "rows");
  exclusive("res", "cols");
  exclusive("motion", "trajectory");
  exclusive("handles", "handle-vertices");
}

ResolvedScene SceneFlags::scene_of_steps(int resolution, int steps, double speed) const {
  Scene scene = this->scene();
  const auto given = [&](const char* key) { return options_.count(key) && options_.at(key)->count() > 0; };
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
  for (const auto& [key, option] : options_)
    if (option->count() > 0) settings[key] = values_.at(key);
  if (!obstacles_.empty()) {
    std::string specs;
    for (const std::string& spec : obstacles_) specs += (specs.empty() ? "" : ";") + spec;
    settings["obstacle"] = specs;
  }
  if (repulsion_flag_ && repulsion_flag_->count() > 0) settings["repulsion"] = "true";
  if (no_repulsion_flag_ && no_repulsion_flag_->count() > 0) settings["repulsion"] = "false";
  return apply_scene_settings(base, settings);
}

}  // namespace fnopt::app
