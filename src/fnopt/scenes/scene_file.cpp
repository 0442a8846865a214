// The scene file format and single settings: the `fnopt simulate` flag names as keys.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_checks.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

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

// Each key parses its value, stores it, and checks the field it set.
using Setter = std::function<void(Scene&, const std::string& key, const std::string& value)>;

const std::map<std::string, Setter>& setters() {
  using namespace scene_checks;
  auto material_field = [](double Material::*field) {
    return [field](Scene& s, const std::string& key, const std::string& value) {
      s.material.*field = number_value(key, value);
      try {
        s.material.validate();
      } catch (const Error& e) {  // named as the user set it (repulsion-stiffness, not _)
        throw Error(key, e.problem());
      }
    };
  };
  auto contact_field = [](double ContactParams::*field) {
    return [field](Scene& s, const std::string& key, const std::string& value) {
      s.contact.*field = number_value(key, value);
      try {
        s.contact.validate();
      } catch (const Error& e) {
        throw Error(key, e.problem());
      }
    };
  };
  static const std::map<std::string, Setter> table = {
      {"res",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.rows = s.cols = int_value(key, value);
         grid_extent(key, s.rows);
       }},
      {"rows",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.rows = int_value(key, value);
         grid_extent(key, s.rows);
       }},
      {"cols",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.cols = int_value(key, value);
         grid_extent(key, s.cols);
       }},
      {"grid-units-of",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.grid_units_of = int_value(key, value);
         if (s.grid_units_of != 0) grid_extent(key, s.grid_units_of);
       }},
      {"size",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.size = number_value(key, value);
         positive(key, s.size, "length in metres");
       }},
      {"material",
       [](Scene& s, const std::string&, const std::string& value) {
         s.material = material_preset(value);
         s.material_name = value;
       }},
      {"stretch", material_field(&Material::stretch)},
      {"shear", material_field(&Material::shear)},
      {"bend", material_field(&Material::bend)},
      {"density", material_field(&Material::density)},
      {"damping", material_field(&Material::damping)},
      {"handles",
       [](Scene& s, const std::string&, const std::string& value) {
         handle_preset_name(value);
         s.handles = value;
         s.handle_vertices.clear();  // a later preset overrides an earlier explicit list
       }},
      {"handle-vertices",
       [](Scene& s, const std::string&, const std::string& value) {
         if (!value.empty()) parse_handle_list(value);  // ranges need the grid: validate()
         s.handle_vertices = value;
       }},
      {"motion",
       [](Scene& s, const std::string&, const std::string& value) {
         motion_name(value);
         s.motion = value;
         s.trajectory.clear();  // a later motion overrides an earlier CSV
       }},
      {"trajectory", [](Scene& s, const std::string&, const std::string& value) { s.trajectory = value; }},
      {"speed",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.speed = number_value(key, value);
         positive(key, s.speed, "factor");
       }},
      {"dt",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.dt = time_step_value(value);
         positive(key, s.dt, "time step in seconds");
       }},
      {"frames",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.frames = int_value(key, value);
         frame_count(s.frames);
       }},
      {"gravity",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.gravity = vector_value(key, value);
         gravity(s.gravity);
       }},
      {"repulsion", [](Scene& s, const std::string& key,
                       const std::string& value) { s.repulsion = repulsion_mode_value(key, value); }},
      {"repulsion-stiffness", material_field(&Material::repulsion_stiffness)},
      {"repulsion-range", material_field(&Material::repulsion_range)},
      {"placement", [](Scene& s, const std::string& key,
                       const std::string& value) { s.placement = placement_value(key, value); }},
      {"let-go",
       [](Scene& s, const std::string& key, const std::string& value) {
         s.let_go = number_value(key, value);
         require(std::isfinite(s.let_go) && s.let_go >= 0.0, key, "must be a time in seconds >= 0");
       }},
      {"obstacle",
       [](Scene& s, const std::string&, const std::string& value) {
         if (value.empty()) {
           s.obstacles.clear();  // an empty line clears the obstacles before it
           return;
         }
         for (Obstacle& o : parse_obstacles(value)) s.obstacles.push_back(std::move(o));
       }},
      {"contact-stiffness", contact_field(&ContactParams::stiffness)},
      {"contact-range", contact_field(&ContactParams::range_fraction)},
      {"contact-thickness", contact_field(&ContactParams::thickness)},
  };
  return table;
}

std::vector<std::string> setting_names() {
  std::vector<std::string> names;
  for (const auto& entry : setters()) names.push_back(entry.first);
  return names;
}

// Shortest text that reads back as exactly the same double.
std::string exact(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// A relative path in a scene file means relative to that file; in a Scene it means relative
// to the working directory, like a path given as a flag.
std::string relative_to(const fs::path& directory, const std::string& path) {
  if (directory.empty() || fs::path(path).is_absolute()) return path;
  return (directory / path).string();
}

// The path= files of obstacle specs, each taken relative to `directory`.
std::string obstacle_paths_relative_to(const fs::path& directory, const std::string& specs) {
  if (directory.empty()) return specs;
  std::string rebased;
  std::size_t copied = 0;
  for (std::size_t key = specs.find("path="); key != std::string::npos; key = specs.find("path=", key + 5)) {
    if (key > 0 && specs[key - 1] != ' ' && specs[key - 1] != '\t') continue;
    const std::size_t start = key + 5;
    const std::size_t end = std::min(specs.find_first_of(" \t;", start), specs.size());
    rebased.append(specs, copied, start - copied);
    rebased += relative_to(directory, specs.substr(start, end - start));
    copied = end;
  }
  return rebased + specs.substr(copied);
}

// A material value is a preset name or a file; only an existing file next to the scene file
// is rebased, so preset names pass through untouched.
std::string material_relative_to(const fs::path& directory, const std::string& name) {
  std::error_code ignored;
  const std::string rebased = relative_to(directory, name);
  return fs::is_regular_file(rebased, ignored) ? rebased : name;
}

// The line without its comment: '#' at the start or after a blank, so that "file.csv#motion"
// keeps its '#'.
std::string_view without_comment(std::string_view line) {
  for (std::size_t at = line.find('#'); at != std::string_view::npos; at = line.find('#', at + 1))
    if (at == 0 || line[at - 1] == ' ' || line[at - 1] == '\t') return line.substr(0, at);
  return line;
}

}  // namespace

void apply_scene_setting(Scene& scene, const std::string& key, const std::string& value) {
  const auto setter = setters().find(key);
  require(setter != setters().end(), key, "unknown setting (valid: " + joined(setting_names()) + ")");
  const std::string text(trim(value));
  // An empty list or path clears it, so that a later file or flag can undo an earlier one.
  require(!text.empty() || key == "handle-vertices" || key == "trajectory" || key == "obstacle", key,
          "expected a value after '='");
  setter->second(scene, key, text);
  resolve_repulsion(scene);  // handles, handle-vertices, repulsion and material all bear on it
}

namespace {

// The settings of a scene file's lines, on top of `base`; `name` starts every error message and
// relative paths are taken relative to `directory` (none if it is empty).
Scene read_scene_lines(std::istream& in, const std::string& name, const fs::path& directory, Scene base) {
  std::string line;
  int number = 0;
  std::map<std::string, int> seen;  // key -> line
  while (std::getline(in, line)) {
    ++number;
    const std::string where = name + ":" + std::to_string(number) + ": ";
    // A binary file is refused without echoing its bytes to the terminal.
    if (!std::all_of(line.begin(), line.end(), [](unsigned char c) { return c >= 32 || c == '\t' || c == '\r'; }))
      throw Error(where + "not a text scene file (control or binary bytes)");
    const auto content = trim(without_comment(line));
    if (content.empty()) continue;
    const auto equals = content.find('=');
    if (equals == std::string_view::npos) {
      const std::string shown(content.substr(0, 60));
      throw Error(where + "expected 'key = value', got '" + shown + (content.size() > 60 ? "...'" : "'"));
    }
    const std::string key(trim(content.substr(0, equals)));
    std::string value(trim(content.substr(equals + 1)));
    if (key.empty()) throw Error(where + "missing key before '='");
    if (!seen.emplace(key, number).second && key != "obstacle")
      throw Error(where + key + ": given twice (first on line " + std::to_string(seen[key]) + ")");
    if (key == "trajectory" && !value.empty()) value = relative_to(directory, value);
    if (key == "material") value = material_relative_to(directory, value);
    if (key == "obstacle") value = obstacle_paths_relative_to(directory, value);
    try {
      apply_scene_setting(base, key, value);
    } catch (const Error& e) {
      throw Error(where + e.what());
    }
  }
  return base;
}

}  // namespace

Scene load_scene_file(const std::string& path, Scene base) {
  std::error_code ignored;
  std::ifstream in(path);
  require(in && !fs::is_directory(path, ignored), "scene", "cannot open '" + path + "'");
  base = read_scene_lines(in, path, fs::path(path).parent_path(), std::move(base));
  require(!in.bad(), "scene", "cannot read '" + path + "'");
  return base;
}

Scene load_scene_text(const std::string& text, const std::string& name, Scene base) {
  std::istringstream in(text);
  return read_scene_lines(in, name, {}, std::move(base));
}

std::string to_scene_text(const Scene& scene) {
  // Paths are written absolute: the text may be read again from another directory.
  std::error_code ignored;
  auto absolute = [&](const std::string& path) { return fs::absolute(path, ignored).string(); };
  const bool material_is_file = fs::is_regular_file(scene.material_name, ignored);
  std::ostringstream out;
  out << "# fnopt scene\n"
      << "rows = " << scene.rows << "\n"
      << "cols = " << scene.cols << "\n"
      << "size = " << exact(scene.size) << "\n";
  if (scene.grid_units_of != 0) out << "grid-units-of = " << scene.grid_units_of << "\n";
  out << "material = " << (material_is_file ? absolute(scene.material_name) : scene.material_name) << "\n"
      << "stretch = " << exact(scene.material.stretch) << "\n"
      << "shear = " << exact(scene.material.shear) << "\n"
      << "bend = " << exact(scene.material.bend) << "\n"
      << "density = " << exact(scene.material.density) << "\n"
      << "damping = " << exact(scene.material.damping) << "\n"
      << "handles = " << scene.handles << "\n";
  if (!scene.handle_vertices.empty()) out << "handle-vertices = " << scene.handle_vertices << "\n";
  out << "motion = " << scene.motion << "\n";
  if (!scene.trajectory.empty()) out << "trajectory = " << absolute(scene.trajectory) << "\n";
  out << "speed = " << exact(scene.speed) << "\n"
      << "dt = " << exact(scene.dt) << "\n"
      << "frames = " << scene.frames << "\n"
      << "gravity = " << exact(scene.gravity.x()) << "," << exact(scene.gravity.y()) << "," << exact(scene.gravity.z())
      << "\n"
      << "repulsion = " << repulsion_mode_name(scene.repulsion)
      << "  # resolved: " << (repulsion_enabled(scene) ? "on" : "off") << "\n"
      << "repulsion-stiffness = " << exact(scene.material.repulsion_stiffness) << "\n"
      << "repulsion-range = " << exact(scene.material.repulsion_range) << "\n";
  if (scene.placement != Placement::Vertical) out << "placement = " << placement_name(scene.placement) << "\n";
  if (scene.let_go >= 0.0) out << "let-go = " << exact(scene.let_go) << "\n";
  if (!scene.obstacles.empty()) {
    for (const Obstacle& o : scene.obstacles) out << "obstacle = " << o.to_text() << "\n";
    out << "contact-stiffness = " << exact(scene.contact.stiffness) << "\n"
        << "contact-range = " << exact(scene.contact.range_fraction) << "\n"
        << "contact-thickness = " << exact(scene.contact.thickness) << "\n";
  }
  return out.str();
}

}  // namespace fnopt
