// fnopt.Scene: the command line's scene, from the same settings with the same checks and texts.
#include <pybind11/stl.h>

#include <sstream>

#include <fnopt/scenes/scene.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/util/error.hpp>

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

// Keyword arguments as settings: handle_vertices -> handle-vertices, as on the command line.
std::map<std::string, std::string> settings_of(const py::kwargs& keywords) {
  std::map<std::string, std::string> settings;
  for (const auto& [key, value] : keywords) {
    std::string name = key.cast<std::string>();
    for (char& c : name)
      if (c == '_') c = '-';
    settings[name] = setting_text(value);
  }
  return settings;
}

Scene make_scene(const py::object& file, const py::kwargs& keywords) {
  const Scene base = file.is_none() ? Scene{} : load_scene_file(py::str(file).cast<std::string>());
  return apply_scene_settings(base, settings_of(keywords));
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
  py::class_<Scene>(m, "Scene", R"(A scene: grid, material, handles and their motion, time step and frames.

Checked as the command line checks it: a bad value raises fnopt.Error (a ValueError) with the
command line's text. Two scenes are equal when their scene files' texts are.

Parameters
----------
scene : str or os.PathLike, optional
    A scene file (key = value lines) the keywords apply on top of; default: the defaults.
**settings
    The flags of ``fnopt simulate`` with '_' for '-': res, rows, cols, size, grid_units_of,
    material, stretch, shear, bend, density, damping, handles, handle_vertices (pairs or
    "i,j;i,j"), motion, trajectory, speed, frames, dt, gravity (x, y, z), repulsion,
    repulsion_stiffness, repulsion_range.)")
      .def(py::init(&make_scene), py::arg("scene") = py::none())
      .def(
          "replace",
          [](const Scene& self, const py::kwargs& keywords) {
            return apply_scene_settings(self, settings_of(keywords));
          },
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
      .def(
          "__repr__",
          [](const Scene& s) {
            std::ostringstream text;
            text << "Scene(rows=" << s.rows << ", cols=" << s.cols << ", handles='"
                 << (s.handle_vertices.empty() ? s.handles : s.handle_vertices) << "', motion='"
                 << (s.trajectory.empty() ? s.motion : s.trajectory) << "', frames=" << s.frames << ", dt=" << s.dt
                 << ")";
            return text.str();
          },
          R"(The scene's grid, handles, motion, frames and time step.

Returns
-------
str
    ``Scene(rows=32, cols=32, handles='corner', motion='xy_v2', frames=390, dt=0.0166667)``)");
}

}  // namespace fnopt::python
