#pragma once
// A scene: everything a rollout needs except the optimizer (docs/design.md §7). Built from defaults,
// a preset, a scene file and command-line flags, in that order; validated once, then resolved
// into the grid, handles and trajectory it names.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fnopt/boundary/handles.hpp>
#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/material.hpp>
#include <fnopt/contact/contact_params.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/contact/self_contact_params.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

// A setting that is on, off, or decided by the rest of the scene (repulsion_enabled,
// self_contact_enabled).
enum class AutoSwitch { Auto, On, Off };
using RepulsionMode = AutoSwitch;

// Where the cloth rests at t = 0: vertical, vertex (i, j) at (j h, 0, -i h) (docs/design.md §7), or
// horizontal, in the x-y plane at z = 0 centred on the z axis: (j h - w/2, h_r/2 - i h, 0) with w and
// h_r the cloth's width and height.
enum class Placement { Vertical, Horizontal };

struct Scene {
  int rows = 32;
  int cols = 32;
  double size = 1.0;  // side of the longer edge [m]
  std::string material_name = "default";
  Material material;               // resolved values (material_preset, then overrides)
  std::string handles = "corner";  // preset name
  std::string handle_vertices;     // explicit "i,j;..." list; overrides `handles` if set
  std::string motion = "xy_v2";
  std::string trajectory;  // CSV path; overrides `motion` if set
  double speed = 1.0;      // handle speed factor alpha
  double dt = 1.0 / 60.0;  // [s]
  int frames = 390;
  Vec3 gravity{0.0, 0.0, -9.81};  // [m/s^2]
  RepulsionMode repulsion = RepulsionMode::Auto;
  // The paper's protocol (docs/design.md §2): N0 > 0 holds the grid-unit material and gravity
  // (k~_s, k~_sh, k~_b, g~) at the values this scene has on an N0 x N0 grid of the same size, at
  // every resolution; resolve() rescales stretch and shear by (h/h0)^2, bend by (h/h0)^4 and
  // gravity by h/h0. 0 (the default): one physical cloth, whose grid-unit stiffness grows with N.
  int grid_units_of = 0;
  Placement placement = Placement::Vertical;
  // Every handle released at this time [s]: the steps that end after it leave the handle vertices
  // free. Negative: never (the default).
  double let_go = -1.0;
  // Obstacles the cloth cannot enter and their contact settings (docs/design.md §14).
  std::vector<Obstacle> obstacles;
  ContactParams contact;
  // Self-contact (docs/design.md §14): on, off, or auto (see self_contact_enabled), and its barrier.
  AutoSwitch self_contact = AutoSwitch::Auto;
  SelfContactParams self_contact_params;

  // Checks every field; throws Error("<field>: <problem>") for the first bad one (rows < 3,
  // size, dt, frames <= 0, speed <= 0, non-finite gravity, material.*, unknown handle preset or
  // motion name, a handle-vertices entry that is malformed or off the grid, a rot_h1 motion with
  // one handle, contact.*, a cloth that starts within the thickness of an obstacle: "obstacle 1:
  // the cloth starts inside it at vertex (i,j)"). NaN fails every check. Does not open files:
  // resolve() does.
  void validate() const;
  // Refuses a cloth that starts within the thickness of a mesh obstacle or inside a closed one.
  void refuse_mesh_start(const Grid& grid, const VecX& rest) const;
};

// Scene file: one "key = value" per line, blank lines ignored; '#' at the start of a line or
// after a blank starts a comment (so "trajectory = motions.csv#xy_v2" keeps its '#'). The keys,
// their values and checks are the table of scene_keys.hpp; only a repeatable key (obstacle) may
// stand on several lines, each adding to it, and an empty value clears a key that allows it
// (handle-vertices, trajectory, obstacle).
// Settings apply in order on top of `base`, later ones winning: `material = NAME` resets all
// material values to material_preset(NAME) and later stretch/shear/bend/density/damping lines
// override single values; `handles` clears an earlier handle-vertices and `motion` an earlier
// trajectory. A relative trajectory path, an obstacle's path= file, or a material file next to
// the scene file, is taken relative to the scene file. Throws
// Error("<path>:<line>: <key>: ...") for an unknown key, a malformed or out-of-range value
// (the checks of Scene::validate that need no other field), and Error("scene", "...") for an
// unreadable file.
Scene load_scene_file(const std::string& path, Scene base = {});
// The same format from memory (e.g. the scene a rollout file stores): `name` starts every error
// message ("<name>:<line>: <key>: ..."); relative paths are taken as given.
Scene load_scene_text(const std::string& text, const std::string& name, Scene base = {});
// Applies one "key = value" setting (a key of scene_keys.hpp, with its checks; paths taken as
// given). Throws Error("<key>: ...").
void apply_scene_setting(Scene& scene, const std::string& key, const std::string& value);
// The one rule for self-contact: On and Off as given; Auto is on where the cloth can fold onto
// itself: a released cloth (handles `none`, or let-go), a scene with obstacles, and the handle
// presets whose cloth folds, `corner-center` and `single-mid-edge`. Off for the paper's hanging
// benchmark (corner handles, no obstacles).
bool self_contact_enabled(const Scene& scene);
// The self-contact settings where self_contact_enabled, else none (what the objective takes).
std::optional<SelfContactParams> self_contact_of(const Scene& scene);
// The one rule for self-repulsion: On and Off as given; Auto is on for the folding presets
// `corner-center` and `single-mid-edge` (not for an explicit handle-vertices list) where
// self-contact is off: self-contact takes its place.
bool repulsion_enabled(const Scene& scene);
// "auto", "true" or "false".
std::string repulsion_mode_name(AutoSwitch mode);
// Writes repulsion_enabled(scene) into scene.material.repulsion, which is what the objective
// reads. apply_scene_setting (so scene files and flags) does this after every setting; code
// that changes scene.repulsion, handles or handle_vertices directly calls it before a rollout.
void resolve_repulsion(Scene& scene);

// The scene as "key = value" lines, readable again by load_scene_file into an identical scene
// (numbers are written exactly; trajectory and material-file paths are made absolute).
std::string to_scene_text(const Scene& scene);

// A scene resolved once, at the edge (a command, a study), into what a rollout needs: the grid,
// the handle vertices and the trajectory, with the scene's physical settings beside them.
// Cheap to copy: the trajectory (possibly read from a CSV) is shared and immutable.
struct ResolvedScene {
  Scene scene;
  Grid grid;
  HandleSet handles;
  std::shared_ptr<const HandleTrajectory> trajectory;
  VecX rest_positions;  // the cloth at t = 0, as the scene places it

  // rest_positions, or the grid's rest pose where a scene assembled by hand left them empty.
  VecX start_positions() const {
    return rest_positions.size() == grid.dof_count() ? rest_positions : grid.rest_positions();
  }
};
// The cloth's positions at t = 0 on `grid` as `placement` puts it.
VecX placed_rest_positions(const Grid& grid, Placement placement);
// "vertical" or "horizontal".
std::string placement_name(Placement placement);
// The scene with grid_units_of applied: its material and gravity rescaled to those physical
// values that give this grid the grid-unit numbers of the N0 grid, and grid_units_of = 0. The
// scene itself when grid_units_of is 0.
Scene with_grid_units_applied(const Scene& scene);

// Validates first, then applies grid_units_of (the resolved scene holds the physical values the
// objective uses); an explicit handle-vertices list beats the handles preset, a trajectory CSV
// beats the motion (whose rest positions are the handle vertices' in grid.rest_positions()).
// Throws Error("trajectory", "...") for a CSV that cannot be replayed on this scene's handles.
ResolvedScene resolve(const Scene& scene);

}  // namespace fnopt
