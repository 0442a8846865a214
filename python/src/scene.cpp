// fnopt.Scene: the command line's scene, from the same table of keys with the same checks and texts.
#include <pybind11/stl.h>

#include <set>
#include <sstream>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_keys.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

#include "common.hpp"

namespace fnopt::python {
namespace {

// A keyword argument as the command line would spell its value: True/False as true/false,
// a sequence as "x,y,z" (gravity) or "i,j;i,j" (handle_vertices, a sequence of pairs), numbers
// in Python's shortest exact form.
std::string setting_text(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::sequence>(value) || py::isinstance<py::array>(value)) {
    std::string text;
    for (const py::handle item : value) {
      const bool pair = py::isinstance<py::sequence>(item) && !py::isinstance<py::str>(item);
      if (!text.empty()) text += pair ? ";" : ",";
      text += setting_text(item);
    }
    return text;
  }
  return py::str(value).cast<std::string>();
}

// Keyword arguments as settings, by the scene key table (scenes/scene_keys.hpp): handle_vertices
// is the key handle-vertices; obstacles, a list of specs, arrive as obstacles, each parsed once.
struct KeywordSettings {
  std::map<std::string, std::string> values;
  std::vector<Obstacle> obstacles;
};

KeywordSettings settings_of(const py::kwargs& keywords) {
  KeywordSettings settings;
  for (const auto& [keyword, value] : keywords) {
    const std::string name = keyword.cast<std::string>();
    const SceneKey* key = find_scene_keyword(name);
    if (key && key->type == SceneKeyType::Obstacles && !py::isinstance<py::str>(value)) {
      for (const py::handle spec : value) settings.obstacles.push_back(parse_obstacle(py::str(spec)));
      continue;
    }
    std::string setting = key ? key->name : name;  // an unknown name fails, with the valid keys
    for (char& c : setting)
      if (c == '_') c = '-';
    settings.values[setting] = setting_text(value);
  }
  return settings;
}

Scene with_keywords(const Scene& base, const py::kwargs& keywords) {
  const KeywordSettings settings = settings_of(keywords);
  return apply_scene_settings(base, settings.values, settings.obstacles);
}

Scene make_scene(const py::object& file, const py::kwargs& keywords) {
  return with_keywords(file.is_none() ? Scene{} : load_scene_file(py::str(file).cast<std::string>()), keywords);
}

// A value of the scene file as a Python literal of its keyword: text quoted, x,y,z as a tuple.
std::string python_literal(const SceneKey& key, const std::string& value) {
  switch (key.type) {
    case SceneKeyType::Integer:
    case SceneKeyType::Number:
      return value;
    case SceneKeyType::Vector3: {
      std::vector<std::string> parts;
      for (const std::string_view part : split(value, ',')) parts.emplace_back(part);
      return "(" + joined(parts) + ")";
    }
    default:
      return py::repr(py::str(value)).cast<std::string>();
  }
}

// Scene(...) with the keywords that make this scene: the grid, material, handles, motion, frames
// and dt always, every other key where it differs from the defaults'.
std::string scene_repr(const Scene& scene) {
  static const std::set<std::string> always = {"rows", "cols", "material", "handles", "motion", "frames", "dt"};
  std::vector<std::string> keywords;
  for (const SceneKey& key : scene_keys()) {
    if (!key.accepted_by(kPython)) continue;
    std::vector<std::string> values, defaults;
    key.codec.write(scene, values);
    key.codec.write(Scene{}, defaults);
    if (values.empty() || (values == defaults && !always.count(key.name))) continue;
    std::vector<std::string> literals;
    for (const std::string& value : values) literals.push_back(python_literal(key, value));
    const std::string text = key.repeatable() ? "[" + joined(literals, ", ") + "]" : literals.front();
    keywords.push_back(key.python_keyword() + "=" + text);
  }
  return "Scene(" + joined(keywords, ", ") + ")";
}

// The class docstring, with one entry per keyword of the scene key table.
const std::string& scene_doc() {
  static const std::string doc = [] {
    std::string text = R"(A scene: grid, material, handles and their motion, time step and frames, obstacles.

Checked as the command line checks it: a bad value raises fnopt.Error (a ValueError) with the
command line's text. Two scenes are equal when their scene files' texts are. ``fnopt.scene_keys()``
lists the keywords with their types, units and defaults.

Parameters
----------
scene : str or os.PathLike, optional
    A scene file (key = value lines) the keywords apply on top of; default: the defaults.
**settings
    The flags of ``fnopt simulate`` with '_' for '-':
)";
    for (const SceneKey& key : scene_keys())
      if (key.accepted_by(kPython))
        text += "\n    " + key.python_keyword() + " (" + to_string(key.type) + "): " + key.help_text() + ".";
    return text;
  }();
  return doc;
}

py::object scene_key_record(const SceneKey& key) {
  using namespace pybind11::literals;
  return record_type("SceneKey")("name"_a = key.name, "keyword"_a = key.python_keyword(),
                                 "type"_a = to_string(key.type), "unit"_a = key.unit,
                                 "default"_a = key.default_text, "help"_a = key.help, "example"_a = key.example);
}

// Scene::handle_vertices' "i,j;i,j" text (already checked) as (row, column) pairs.
py::list vertex_pairs(const std::string& text) {
  py::list pairs;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    const std::size_t comma = entry.find(',');
    if (comma == std::string::npos) continue;
    pairs.append(py::make_tuple(std::stoi(entry.substr(0, comma)), std::stoi(entry.substr(comma + 1))));
  }
  return pairs;
}

py::object material_record(const Scene& s) {
  using namespace pybind11::literals;
  const Material& m = s.material;
  return record_type("Material")("name"_a = s.material_name, "stretch"_a = m.stretch, "shear"_a = m.shear,
                                 "bend"_a = m.bend, "density"_a = m.density, "damping"_a = m.damping,
                                 "repulsion"_a = m.repulsion, "repulsion_stiffness"_a = m.repulsion_stiffness,
                                 "repulsion_range"_a = m.repulsion_range);
}

}  // namespace

void define_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", scene_doc().c_str())
      .def(py::init(&make_scene), py::arg("scene") = py::none())
      .def(
          "replace",
          [](const Scene& self, const py::kwargs& keywords) { return with_keywords(self, keywords); },
          R"(A copy with the given settings applied on top.

Parameters
----------
**settings
    The keywords of Scene().

Returns
-------
Scene
    The new scene; this one is unchanged.)")
      .def_static(
          "load",
          [](const std::string& path) {
            Scene scene = load_scene_file(path);
            scene.validate();
            return scene;
          },
          py::arg("path"), R"(Reads a scene file.

Parameters
----------
path : str
    A scene file: ``key = value`` lines, the keys the command line's flags.

Returns
-------
Scene
    The checked scene.)")
      .def_readonly("rows", &Scene::rows, "int: The grid's rows of vertices.")
      .def_readonly("cols", &Scene::cols, "int: The grid's columns of vertices.")
      .def_readonly("size", &Scene::size, "float: The longer edge's length in metres.")
      .def_readonly("grid_units_of", &Scene::grid_units_of,
                    "int: N0 > 0 holds the grid-unit material and gravity of an N0 x N0 grid; 0: one physical cloth.")
      .def_readonly("frames", &Scene::frames, "int: The frames a rollout runs.")
      .def_readonly("dt", &Scene::dt, "float: The time step in seconds.")
      .def_readonly("speed", &Scene::speed, "float: The handles' speed factor.")
      .def_readonly("handles", &Scene::handles, "str: The handle preset (used unless handle_vertices is set).")
      .def_property_readonly(
          "handle_vertices", [](const Scene& s) { return vertex_pairs(s.handle_vertices); },
          "list of (int, int): The explicit handles' (row, column), empty when the preset is used.")
      .def_readonly("motion", &Scene::motion, "str: The handles' motion (used unless trajectory is set).")
      .def_readonly("trajectory", &Scene::trajectory, "str: A trajectory CSV that overrides motion, or empty.")
      .def_property_readonly(
          "gravity", [](const Scene& s) { return py::make_tuple(s.gravity.x(), s.gravity.y(), s.gravity.z()); },
          "tuple of float: Gravity (x, y, z) in m/s^2.")
      .def_property_readonly(
          "obstacles",
          [](const Scene& s) {
            std::vector<std::string> specs;
            for (const Obstacle& o : s.obstacles) specs.push_back(o.to_text());
            return specs;
          },
          "list of str: The obstacles' specs (``Scene(obstacles=[...])``, ``--obstacle``), empty for none.")
      .def_property_readonly("material", &material_record, "Material: The resolved material's values (SI units).")
      .def_property_readonly("text", &to_scene_text, "str: The scene as a scene file's text (exact numbers).")
      .def(
          "__eq__",
          [](const Scene& self, const py::object& other) -> py::object {
            if (!py::isinstance<Scene>(other)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
            return py::bool_(to_scene_text(self) == to_scene_text(other.cast<const Scene&>()));
          },
          py::arg("other"), R"(Equality of the scene files' texts.

Parameters
----------
other : object
    Another scene.

Returns
-------
bool
    True if both would write the same scene file.)")
      .def("__repr__", &scene_repr, R"(The keywords that make this scene.

Returns
-------
str
    ``Scene(rows=32, cols=32, material='default', handles='corner', motion='xy_v2', dt=0.016666666666666666,
    frames=390)``, with every other keyword whose value is not the default's (material values,
    gravity, obstacles, ...).)");
  m.def(
      "scene_keys", [] {
        py::list keys;
        for (const SceneKey& key : scene_keys())
          if (key.accepted_by(kPython)) keys.append(scene_key_record(key));
        return keys;
      },
      R"(Every keyword of Scene, from the table the command line's flags and scene files share.

Returns
-------
list of SceneKey
    Each keyword's scene-file key, type, unit, default, help text and an example value, in the order
    they apply.)");
}

}  // namespace fnopt::python
