#include <fnopt/scenes/scene_keys.hpp>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <iterator>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/scenes/scene_checks.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;
using Values = std::vector<std::string>;

// ---- values as text ----

int int_value(const std::string& key, const std::string& value) {
  int parsed = 0;
  require(parse_int(value, parsed), key, "expected an integer, got '" + value + "'");
  return parsed;
}

double number_value(const std::string& key, const std::string& value) {
  double parsed = 0.0;
  require(parse_double(value, parsed), key, "expected a number, got '" + value + "'");
  return parsed;
}

// A time step may be written as the fraction it usually is: "1/60".
double time_step_value(const std::string& value) {
  const auto parts = split(value, '/');
  if (parts.size() == 1) return number_value("dt", value);
  double numerator = 0.0, denominator = 0.0;
  require(parts.size() == 2 && parse_double(parts[0], numerator) && parse_double(parts[1], denominator) &&
              denominator != 0.0,
          "dt", "expected a number or a fraction like 1/60, got '" + value + "'");
  return numerator / denominator;
}

Vec3 vector_value(const std::string& key, const std::string& value) {
  const auto parts = split(value, ',');
  Vec3 parsed;
  require(parts.size() == 3 && parse_double(parts[0], parsed.x()) && parse_double(parts[1], parsed.y()) &&
              parse_double(parts[2], parsed.z()),
          key, "expected three numbers \"x,y,z\", got '" + value + "'");
  return parsed;
}

RepulsionMode repulsion_mode_value(const std::string& key, const std::string& value) {
  if (value == "auto") return RepulsionMode::Auto;
  if (value == "true" || value == "1" || value == "on") return RepulsionMode::On;
  if (value == "false" || value == "0" || value == "off") return RepulsionMode::Off;
  throw Error(key + ": expected auto, true or false, got '" + value + "'");
}

Placement placement_value(const std::string& key, const std::string& value) {
  if (value == "vertical") return Placement::Vertical;
  if (value == "horizontal") return Placement::Horizontal;
  throw Error(key, "expected vertical or horizontal, got '" + value + "'");
}

// Shortest text that reads back as exactly the same double.
std::string exact(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// A path as the scene text stores it: absolute, since the text may be read from another directory.
std::string absolute(const std::string& path) {
  std::error_code ignored;
  return fs::absolute(path, ignored).string();
}

// Runs `check`, naming its error as the user set the value (repulsion-stiffness, not
// material.repulsion_stiffness).
template <class Check>
void checked_as(const std::string& key, Check&& check) {
  try {
    check();
  } catch (const Error& e) {
    throw Error(key, e.problem());
  }
}

// ---- paths relative to a scene file ----

// A relative path in a scene file means relative to that file; in a Scene it means relative
// to the working directory, like a path given as a flag.
std::string relative_to(const std::string& directory, const std::string& path) {
  if (directory.empty() || path.empty() || fs::path(path).is_absolute()) return path;
  return (fs::path(directory) / path).string();
}

// A material value is a preset name or a file; only an existing file next to the scene file
// is rebased, so preset names pass through untouched.
std::string material_relative_to(const std::string& directory, const std::string& name) {
  std::error_code ignored;
  const std::string rebased = relative_to(directory, name);
  return fs::is_regular_file(rebased, ignored) ? rebased : name;
}

// The files of obstacle specs (path=, and a mesh's file= and sequence=), each taken relative to
// `directory`.
std::string obstacle_paths_relative_to(const std::string& directory, const std::string& specs) {
  if (directory.empty()) return specs;
  std::string rebased = specs;
  for (const std::string key : {"path=", "file=", "sequence="}) {
    std::string out;
    std::size_t copied = 0;
    for (std::size_t at = rebased.find(key); at != std::string::npos; at = rebased.find(key, at + key.size())) {
      if (at > 0 && rebased[at - 1] != ' ' && rebased[at - 1] != '\t') continue;
      const std::size_t start = at + key.size();
      const std::size_t end = std::min(rebased.find_first_of(" \t;", start), rebased.size());
      out.append(rebased, copied, start - copied);
      out += relative_to(directory, rebased.substr(start, end - start));
      copied = end;
    }
    rebased = out + rebased.substr(copied);
  }
  return rebased;
}

// ---- the grid ----

void apply_grid_extent(int& field, const std::string& key, const std::string& value) {
  field = int_value(key, value);
  scene_checks::grid_extent(key, field);
}

void apply_res(Scene& s, const std::string& key, const std::string& value) {
  apply_grid_extent(s.rows, key, value);
  s.cols = s.rows;
}
void apply_rows(Scene& s, const std::string& key, const std::string& value) { apply_grid_extent(s.rows, key, value); }
void apply_cols(Scene& s, const std::string& key, const std::string& value) { apply_grid_extent(s.cols, key, value); }
void write_nothing(const Scene&, Values&) {}
void write_rows(const Scene& s, Values& out) { out.push_back(std::to_string(s.rows)); }
void write_cols(const Scene& s, Values& out) { out.push_back(std::to_string(s.cols)); }

void apply_size(Scene& s, const std::string& key, const std::string& value) {
  s.size = number_value(key, value);
  scene_checks::positive(key, s.size, "length in metres");
}
void write_size(const Scene& s, Values& out) { out.push_back(exact(s.size)); }

void apply_grid_units_of(Scene& s, const std::string& key, const std::string& value) {
  s.grid_units_of = int_value(key, value);
  if (s.grid_units_of != 0) scene_checks::grid_extent(key, s.grid_units_of);
}
void write_grid_units_of(const Scene& s, Values& out) {
  if (s.grid_units_of != 0) out.push_back(std::to_string(s.grid_units_of));
}

// ---- the material ----

void apply_material(Scene& s, const std::string&, const std::string& value) {
  s.material = material_preset(value);
  s.material_name = value;
}
void write_material(const Scene& s, Values& out) {
  std::error_code ignored;
  out.push_back(fs::is_regular_file(s.material_name, ignored) ? absolute(s.material_name) : s.material_name);
}

template <double Material::*Field>
void apply_material_value(Scene& s, const std::string& key, const std::string& value) {
  s.material.*Field = number_value(key, value);
  checked_as(key, [&] { s.material.validate(); });
}
template <double Material::*Field>
void write_material_value(const Scene& s, Values& out) {
  out.push_back(exact(s.material.*Field));
}

// ---- the handles and their motion ----

void apply_handles(Scene& s, const std::string&, const std::string& value) {
  scene_checks::handle_preset_name(value);
  s.handles = value;
  s.handle_vertices.clear();  // a later preset overrides an earlier explicit list
}
void write_handles(const Scene& s, Values& out) { out.push_back(s.handles); }

void apply_handle_vertices(Scene& s, const std::string&, const std::string& value) {
  if (!value.empty()) parse_handle_list(value);  // ranges need the grid: validate()
  s.handle_vertices = value;
}
void write_handle_vertices(const Scene& s, Values& out) {
  if (!s.handle_vertices.empty()) out.push_back(s.handle_vertices);
}

void apply_motion(Scene& s, const std::string&, const std::string& value) {
  scene_checks::motion_name(value);
  s.motion = value;
  s.trajectory.clear();  // a later motion overrides an earlier CSV
}
void write_motion(const Scene& s, Values& out) { out.push_back(s.motion); }

void apply_trajectory(Scene& s, const std::string&, const std::string& value) { s.trajectory = value; }
void write_trajectory(const Scene& s, Values& out) {
  if (!s.trajectory.empty()) out.push_back(absolute(s.trajectory));
}

void apply_speed(Scene& s, const std::string& key, const std::string& value) {
  s.speed = number_value(key, value);
  scene_checks::positive(key, s.speed, "factor");
}
void write_speed(const Scene& s, Values& out) { out.push_back(exact(s.speed)); }

// ---- time ----

void apply_dt(Scene& s, const std::string& key, const std::string& value) {
  s.dt = time_step_value(value);
  scene_checks::positive(key, s.dt, "time step in seconds");
}
void write_dt(const Scene& s, Values& out) { out.push_back(exact(s.dt)); }

void apply_frames(Scene& s, const std::string& key, const std::string& value) {
  s.frames = int_value(key, value);
  scene_checks::frame_count(s.frames);
}
void write_frames(const Scene& s, Values& out) { out.push_back(std::to_string(s.frames)); }

void apply_gravity(Scene& s, const std::string& key, const std::string& value) {
  s.gravity = vector_value(key, value);
  scene_checks::gravity(s.gravity);
}
void write_gravity(const Scene& s, Values& out) {
  out.push_back(exact(s.gravity.x()) + "," + exact(s.gravity.y()) + "," + exact(s.gravity.z()));
}

// ---- self-repulsion ----

void apply_repulsion(Scene& s, const std::string& key, const std::string& value) {
  s.repulsion = repulsion_mode_value(key, value);
}
void write_repulsion(const Scene& s, Values& out) { out.push_back(repulsion_mode_name(s.repulsion)); }

// ---- self-contact ----

void apply_self_contact(Scene& s, const std::string& key, const std::string& value) {
  s.self_contact = repulsion_mode_value(key, value);
}
// Written where it is on or set: the hanging benchmark's scene text is as it was before self-contact.
void write_self_contact(const Scene& s, Values& out) {
  if (s.self_contact != AutoSwitch::Auto || self_contact_enabled(s)) out.push_back(repulsion_mode_name(s.self_contact));
}

template <double SelfContactParams::*Field>
void apply_self_contact_value(Scene& s, const std::string& key, const std::string& value) {
  s.self_contact_params.*Field = number_value(key, value);
  s.self_contact_params.validate();
}
// The barrier's settings are written only where self-contact is on, which they are for.
template <double SelfContactParams::*Field>
void write_self_contact_value(const Scene& s, Values& out) {
  if (self_contact_enabled(s)) out.push_back(exact(s.self_contact_params.*Field));
}

// Friction between layers is written where it acts (so a scene without it reads as before).
void write_self_contact_friction(const Scene& s, Values& out) {
  if (self_contact_enabled(s) && s.self_contact_params.friction != 0.0) out.push_back(exact(s.self_contact_params.friction));
}

// ---- placement and release ----

void apply_placement(Scene& s, const std::string& key, const std::string& value) {
  s.placement = placement_value(key, value);
}
void write_placement(const Scene& s, Values& out) {
  if (s.placement != Placement::Vertical) out.push_back(placement_name(s.placement));
}

void apply_let_go(Scene& s, const std::string& key, const std::string& value) {
  s.let_go = number_value(key, value);
  require(std::isfinite(s.let_go) && s.let_go >= 0.0, key, "must be a time in seconds >= 0");
}
void write_let_go(const Scene& s, Values& out) {
  if (s.let_go >= 0.0) out.push_back(exact(s.let_go));
}

// ---- contact ----

void apply_obstacle(Scene& s, const std::string&, const std::string& value) {
  if (value.empty()) {
    s.obstacles.clear();  // an empty line clears the obstacles before it
    return;
  }
  for (Obstacle& o : parse_obstacles(value)) s.obstacles.push_back(std::move(o));
}
void write_obstacle(const Scene& s, Values& out) {
  for (const Obstacle& o : s.obstacles) out.push_back(o.to_text());
}

template <double ContactParams::*Field>
void apply_contact_value(Scene& s, const std::string& key, const std::string& value) {
  s.contact.*Field = number_value(key, value);
  checked_as(key, [&] { s.contact.validate(); });
}
// The contact settings are written only with obstacles, which they are for.
template <double ContactParams::*Field>
void write_contact_value(const Scene& s, Values& out) {
  if (!s.obstacles.empty()) out.push_back(exact(s.contact.*Field));
}

using T = SceneKeyType;
constexpr unsigned kAll = kEverySurface;

// A constant array, so that it is ready before any static initialiser could ask for it.
// clang-format off
const SceneKey kKeys[] = {
  {"res", T::Integer, "N", "", "32", "grid resolution: N x N vertices", "40", "rows,cols",
   kAll, 0, {apply_res, write_nothing}},
  {"rows", T::Integer, "R", "", "32", "grid rows R (non-square grids)", "24", "cols",
   kAll, 0, {apply_rows, write_rows}},
  {"cols", T::Integer, "C", "", "32", "grid columns C (non-square grids)", "20", "",
   kAll, 0, {apply_cols, write_cols}},
  {"size", T::Number, "M", "m", "1", "side of the cloth's longer edge", "1.5", "",
   kAll, 0, {apply_size, write_size}},
  {"grid-units-of", T::Integer, "N0", "", "0: one physical cloth",
   "hold the material's grid-unit stiffness and gravity at this scene's on an N0 x N0 grid, at any resolution "
   "(the FNOpt paper's protocol; docs/design.md §2)", "32", "",
   kAll, 0, {apply_grid_units_of, write_grid_units_of}},
  {"material", T::Text, "NAME|FILE", "", "default", "material preset or a material file from fit-material",
   "default", "", kAll, 0, {apply_material, write_material, material_relative_to}},
  {"stretch", T::Number, "K", "N/m", "the material's", "stretch stiffness k_s", "80", "",
   kAll, 0, {apply_material_value<&Material::stretch>, write_material_value<&Material::stretch>}},
  {"shear", T::Number, "K", "N/m", "the material's", "shear stiffness k_sh", "2", "",
   kAll, 0, {apply_material_value<&Material::shear>, write_material_value<&Material::shear>}},
  {"bend", T::Number, "K", "N m", "the material's", "bending stiffness k_b", "1e-4", "",
   kAll, 0, {apply_material_value<&Material::bend>, write_material_value<&Material::bend>}},
  {"density", T::Number, "RHO", "kg/m^2", "the material's", "area density rho", "0.2", "",
   kAll, 0, {apply_material_value<&Material::density>, write_material_value<&Material::density>}},
  {"damping", T::Number, "C", "1/s", "the material's", "damping coefficient c", "2", "",
   kAll, 0, {apply_material_value<&Material::damping>, write_material_value<&Material::damping>}},
  {"handles", T::Text, "PRESET", "", "corner",
   "handle preset: corner, diagonal, mid-edge, corner-center, single-mid-edge, single-center, none", "diagonal",
   "handle-vertices", kAll, 0, {apply_handles, write_handles}},
  {"handle-vertices", T::Text, "I,J;I,J", "", "", "explicit handle vertices (overrides handles)", "0,0;0,9", "",
   kAll, kEmptyClears, {apply_handle_vertices, write_handle_vertices}},
  {"motion", T::Text, "NAME", "", "xy_v2", "handle motion: xy_v2, ..., rot_h1_opp, static", "rot_h0", "trajectory",
   kAll, 0, {apply_motion, write_motion}},
  {"trajectory", T::Text, "FILE.csv[#MOTION]", "", "",
   "CSV of handle positions (t_s, hK_x, hK_y, hK_z), overrides motion; FILE.csv#MOTION picks rows",
   "motions.csv#xy_v2", "", kAll, kEmptyClears, {apply_trajectory, write_trajectory, relative_to}},
  {"speed", T::Number, "F", "", "1", "handle speed factor alpha", "1.5", "",
   kAll, 0, {apply_speed, write_speed}},
  {"dt", T::Number, "S", "s", "1/60", "time step (a number or a fraction such as 1/60)", "1/120", "",
   kAll, 0, {apply_dt, write_dt}},
  {"frames", T::Integer, "N", "", "390", "number of time steps", "60", "",
   kAll, 0, {apply_frames, write_frames}},
  {"gravity", T::Vector3, "X,Y,Z", "m/s^2", "0,0,-9.81", "gravity vector", "0,0,-5", "",
   kAll, 0, {apply_gravity, write_gravity}},
  {"repulsion", T::Switch, "auto|true|false", "", "auto: on for corner-center and single-mid-edge",
   "self-repulsion between non-adjacent vertices (docs/design.md §2)", "true", "",
   kAll, 0, {apply_repulsion, write_repulsion, nullptr, repulsion_enabled}},
  {"repulsion-stiffness", T::Number, "LAMBDA", "N/m", "10", "self-repulsion barrier stiffness lambda", "20", "",
   kAll, 0, {apply_material_value<&Material::repulsion_stiffness>, write_material_value<&Material::repulsion_stiffness>}},
  {"repulsion-range", T::Number, "DELTA", "", "1", "self-repulsion range delta, in cell widths h", "0.8", "",
   kAll, 0, {apply_material_value<&Material::repulsion_range>, write_material_value<&Material::repulsion_range>}},
  {"placement", T::Text, "vertical|horizontal", "", "vertical",
   "the cloth at rest: vertical (hanging in the x-z plane) or horizontal (in the x-y plane at z = 0, centred "
   "on the z axis)", "horizontal", "", kAll, 0, {apply_placement, write_placement}},
  {"let-go", T::Number, "T", "s", "never", "release every handle at this time", "0.5", "",
   kAll, 0, {apply_let_go, write_let_go}},
  {"obstacle", T::Obstacles, "SPEC", "", "none",
   "an obstacle, repeatable: 'sphere center=X,Y,Z radius=R', 'plane point=X,Y,Z normal=X,Y,Z', "
   "'box center=X,Y,Z size=SX,SY,SZ rounding=R' or 'capsule a=X,Y,Z b=X,Y,Z radius=R', each with optional "
   "friction=MU and motion=NAME or path=FILE.csv; or mesh file=PATH.obj or sequence=PREFIX fps=F "
   "[scale=S] [offset=X,Y,Z] (docs/design.md §14)",
   "sphere center=0.5,-0.3,-0.5 radius=0.1 friction=0.3", "",
   kAll, kEmptyClears | kRepeatable, {apply_obstacle, write_obstacle, obstacle_paths_relative_to}},
  {"contact-stiffness", T::Number, "KAPPA", "N/m", "10", "obstacle barrier stiffness kappa (docs/design.md §14)",
   "20", "", kAll, 0, {apply_contact_value<&ContactParams::stiffness>, write_contact_value<&ContactParams::stiffness>}},
  {"contact-range", T::Number, "DHAT", "", "0.5", "obstacle barrier range dhat, in cell widths h", "0.25", "",
   kAll, 0, {apply_contact_value<&ContactParams::range_fraction>, write_contact_value<&ContactParams::range_fraction>}},
  {"contact-thickness", T::Number, "D", "m", "0.001", "the gap the barrier keeps from every obstacle", "0.002", "",
   kAll, 0, {apply_contact_value<&ContactParams::thickness>, write_contact_value<&ContactParams::thickness>}},
  {"self-contact", T::Switch, "auto|true|false", "",
   "auto: on for a released cloth, with obstacles and for corner-center and single-mid-edge",
   "self-contact: barriers between the cloth's own triangles, edges and vertices, and CCD (docs/design.md §14)",
   "true", "", kAll, 0, {apply_self_contact, write_self_contact, nullptr, self_contact_enabled}},
  {"self-contact-stiffness", T::Number, "KAPPA", "N/m", "10", "self-contact barrier stiffness kappa", "20", "",
   kAll, 0, {apply_self_contact_value<&SelfContactParams::stiffness>,
             write_self_contact_value<&SelfContactParams::stiffness>}},
  {"self-contact-range", T::Number, "DHAT", "m", "0.0015", "self-contact barrier range dhat", "0.002", "",
   kAll, 0, {apply_self_contact_value<&SelfContactParams::range>, write_self_contact_value<&SelfContactParams::range>}},
  {"self-contact-thickness", T::Number, "D", "m", "0.001", "the gap self-contact keeps between cloth layers",
   "0.0005", "", kAll, 0, {apply_self_contact_value<&SelfContactParams::thickness>,
                           write_self_contact_value<&SelfContactParams::thickness>}},
  {"self-contact-friction", T::Number, "MU", "", "0", "friction coefficient between cloth layers (lagged)", "0.3", "",
   kAll, 0, {apply_self_contact_value<&SelfContactParams::friction>, write_self_contact_friction}},
};
// clang-format on

}  // namespace

std::string SceneKey::python_keyword() const {
  if (type == SceneKeyType::Obstacles) return std::string(name) + "s";
  std::string keyword = name;
  for (char& c : keyword)
    if (c == '-') c = '_';
  return keyword;
}

std::string SceneKey::help_text() const {
  std::string text = help;
  if (*unit) text += std::string(" [") + unit + "]";
  if (*default_text) text += std::string(" (default ") + default_text + ")";
  return text;
}

const std::vector<SceneKey>& scene_keys() {
  static const std::vector<SceneKey> keys(std::begin(kKeys), std::end(kKeys));
  return keys;
}

const SceneKey* find_scene_key(const std::string& name) {
  for (const SceneKey& key : scene_keys())
    if (name == key.name) return &key;
  return nullptr;
}

const SceneKey* find_scene_keyword(const std::string& keyword) {
  for (const SceneKey& key : scene_keys())
    if (keyword == key.python_keyword()) return &key;
  return nullptr;
}

std::vector<std::string> scene_file_lines(const SceneKey& key, const Scene& scene) {
  std::vector<std::string> lines;
  key.codec.write(scene, lines);
  for (std::string& line : lines) {
    line = std::string(key.name) + " = " + line;
    if (key.codec.resolved) line += std::string("  # resolved: ") + (key.codec.resolved(scene) ? "on" : "off");
  }
  return lines;
}

std::string scene_key_names() {
  std::vector<std::string> names;
  for (const SceneKey& key : kKeys) names.push_back(key.name);
  return joined(names);
}

const char* to_string(SceneKeyType type) {
  switch (type) {
    case SceneKeyType::Integer:
      return "int";
    case SceneKeyType::Number:
      return "float";
    case SceneKeyType::Text:
      return "str";
    case SceneKeyType::Vector3:
      return "x,y,z";
    case SceneKeyType::Switch:
      return "auto|true|false";
    case SceneKeyType::Obstacles:
      return "obstacle specs";
  }
  return "unknown";
}

}  // namespace fnopt
