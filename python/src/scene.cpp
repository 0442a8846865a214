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

}  // namespace

void define_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", R"(A scene: grid, material, handles and their motion, time step and frames.

Keyword arguments are the flags of `fnopt simulate` with '_' for '-' (res, rows, cols, size,
grid_units_of, material, stretch, shear, bend, density, damping, handles, handle_vertices, motion,
trajectory, speed, frames, dt, gravity, repulsion, repulsion_stiffness, repulsion_range);
`scene` is a scene file they apply on top of. Checked as the command line checks them:
a bad value raises ValueError with the command line's text.)")
      .def(py::init(&make_scene), py::arg("scene") = py::none())
      .def(
          "replace",
          [](const Scene& self, const py::kwargs& keywords) {
            return apply_scene_settings(self, settings_of(keywords));
          },
          "A copy with the given settings applied (the same keywords as Scene()).")
      .def_static(
          "load",
          [](const std::string& path) {
            Scene scene = load_scene_file(path);
            scene.validate();
            return scene;
          },
          py::arg("path"), "A scene file (key = value lines).")
      .def_readonly("rows", &Scene::rows)
      .def_readonly("cols", &Scene::cols)
      .def_readonly("size", &Scene::size)
      .def_readonly("grid_units_of", &Scene::grid_units_of)
      .def_readonly("frames", &Scene::frames)
      .def_readonly("dt", &Scene::dt)
      .def_readonly("speed", &Scene::speed)
      .def_readonly("handles", &Scene::handles)
      .def_readonly("handle_vertices", &Scene::handle_vertices)
      .def_readonly("motion", &Scene::motion)
      .def_readonly("trajectory", &Scene::trajectory)
      .def_property_readonly("gravity",
                             [](const Scene& s) { return py::make_tuple(s.gravity.x(), s.gravity.y(), s.gravity.z()); })
      .def_property_readonly(
          "material",
          [](const Scene& s) {
            py::dict material;
            material["name"] = s.material_name;
            material["stretch"] = s.material.stretch;
            material["shear"] = s.material.shear;
            material["bend"] = s.material.bend;
            material["density"] = s.material.density;
            material["damping"] = s.material.damping;
            material["repulsion"] = s.material.repulsion;
            material["repulsion_stiffness"] = s.material.repulsion_stiffness;
            material["repulsion_range"] = s.material.repulsion_range;
            return material;
          },
          "The resolved material's values (SI units).")
      .def_property_readonly("text", &to_scene_text, "The scene as a scene file's text (exact numbers).")
      .def("__repr__", [](const Scene& s) {
        std::ostringstream text;
        text << "fnopt.Scene(rows=" << s.rows << ", cols=" << s.cols << ", handles='"
             << (s.handle_vertices.empty() ? s.handles : s.handle_vertices) << "', motion='"
             << (s.trajectory.empty() ? s.motion : s.trajectory) << "', frames=" << s.frames << ")";
        return text.str();
      });
}

}  // namespace fnopt::python
