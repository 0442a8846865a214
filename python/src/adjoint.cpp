// Gradients through rollouts from Python (docs/design.md §15): fnopt.record_rollout records a
// rollout of exact steps (adjoint/recorded_rollout.hpp), RecordedRollout.gradients runs the
// backward pass of a loss given by its dL/dX (adjoint/rollout_adjoint.hpp) and returns the
// gradients by name as NumPy arrays and floats.
#include <pybind11/stl.h>

#include <optional>
#include <sstream>

#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/error.hpp>

#include "common.hpp"
#include "method.hpp"

namespace fnopt::python {
namespace {

struct PyRecordedRollout {
  RecordedRollout record;
  std::string optimizer;
  std::optional<HandlePath> path;  // where the handles followed control points
};

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

DoubleArray double_array(const py::handle& values, const char* field) {
  const auto array = DoubleArray::ensure(values);
  require(static_cast<bool>(array), field, "expected an array of numbers");
  return array;
}

std::string shape_text(std::initializer_list<py::ssize_t> shape) {
  std::string text = "(";
  for (py::ssize_t n : shape) text += (text.size() > 1 ? ", " : "") + std::to_string(n);
  return text + ")";
}

HandlePathBasis path_basis(const std::string& name) {
  if (name == "cubic-bspline") return HandlePathBasis::CubicBSpline;
  if (name == "linear") return HandlePathBasis::PiecewiseLinear;
  throw Error("path_basis", "expected cubic-bspline or linear, got '" + name + "'");
}

// (handles, K, 3) control points of a handle path.
HandleControlPoints control_points(const py::handle& values, int handles) {
  const DoubleArray array = double_array(values, "handle_path");
  require(array.ndim() == 3 && array.shape(0) == handles && array.shape(1) >= 1 && array.shape(2) == 3, "handle_path",
          "expected shape (" + std::to_string(handles) + ", K, 3): K control points per handle");
  HandleControlPoints control(handles, std::vector<Vec3>(array.shape(1)));
  for (int h = 0; h < handles; ++h)
    for (py::ssize_t k = 0; k < array.shape(1); ++k)
      control[h][k] = Vec3(array.at(h, k, 0), array.at(h, k, 1), array.at(h, k, 2));
  return control;
}

// (steps, handles, 3) targets, one row per step.
std::vector<std::vector<Vec3>> step_targets(const py::handle& values, int steps, int handles) {
  const DoubleArray array = double_array(values, "handle_targets");
  require(array.ndim() == 3 && array.shape(0) == steps && array.shape(1) == handles && array.shape(2) == 3,
          "handle_targets", "expected shape " + shape_text({steps, handles, 3}));
  std::vector<std::vector<Vec3>> targets(steps, std::vector<Vec3>(handles));
  for (int s = 0; s < steps; ++s)
    for (int h = 0; h < handles; ++h) targets[s][h] = Vec3(array.at(s, h, 0), array.at(s, h, 1), array.at(s, h, 2));
  return targets;
}

py::array_t<double> targets_array(const std::vector<std::vector<Vec3>>& targets, int handles) {
  py::array_t<double> array(
      {static_cast<py::ssize_t>(targets.size()), static_cast<py::ssize_t>(handles), py::ssize_t{3}});
  auto out = array.mutable_unchecked<3>();
  for (std::size_t s = 0; s < targets.size(); ++s)
    for (int h = 0; h < handles; ++h)
      for (int d = 0; d < 3; ++d) out(s, h, d) = targets[s][h][d];
  return array;
}

PyRecordedRollout record(const Scene& scene, const std::string& optimizer, int iters, const py::object& model,
                         const py::object& lr, const py::object& initial_positions,
                         const py::object& initial_velocities, const py::object& handle_targets,
                         const py::object& handle_path, const std::string& basis) {
  Scene recorded = scene;
  recorded.frames = scene.frames + 1;  // the record counts the initial frame
  const ResolvedScene resolved = resolve(recorded);
  const int rows = resolved.grid.rows, cols = resolved.grid.cols, steps = scene.frames;
  const int handles = static_cast<int>(resolved.handles.vertices.size());
  PyRecordedRollout result;
  result.optimizer = optimizer;
  RolloutInputs inputs;
  if (!initial_positions.is_none())
    inputs.initial_positions = grid_vector(initial_positions, rows, cols, "initial_positions");
  if (!initial_velocities.is_none())
    inputs.initial_velocities = grid_vector(initial_velocities, rows, cols, "initial_velocities");
  require(handle_targets.is_none() || handle_path.is_none(), "handle_path",
          "give handle_targets or handle_path, not both");
  if (!handle_targets.is_none()) inputs.handle_targets = step_targets(handle_targets, steps, handles);
  const HandlePathBasis path_kind = path_basis(basis);
  if (!handle_path.is_none()) {
    const HandleControlPoints control = control_points(handle_path, handles);
    HandlePathParams params;
    params.basis = path_kind;
    params.control_points = static_cast<int>(control.front().size());
    result.path.emplace(params, steps, handles);
    inputs.handle_targets = result.path->targets(resolved, control);
  }
  if (optimizer == "newton") {
    py::gil_scoped_release release;
    result.record = record_rollout(resolved, RecordOptions{}, inputs);
  } else {
    const MethodRun run = method_run(scene, optimizer, iters, model, lr, true, false);
    py::gil_scoped_release release;
    result.record = record_rollout(resolved, *run.optimizer, run.options.solve, RecordOptions{}, inputs);
  }
  return result;
}

// dL/dX as FrameGradients: a (frames, rows, cols, 3) array, or a dict frame -> (rows, cols, 3).
std::vector<FrameGradient> loss_gradient(const PyRecordedRollout& r, const py::handle& values) {
  const int frames = r.record.frame_count(), rows = r.record.scene.grid.rows, cols = r.record.scene.grid.cols;
  std::vector<FrameGradient> gradient;
  if (py::isinstance<py::dict>(values)) {
    for (const auto& [key, value] : values.cast<py::dict>()) {
      require(py::isinstance<py::int_>(key), "dL_dX", "a dict's keys must be frame numbers");
      const int frame = key.cast<int>();
      require(frame >= 0 && frame < frames, "dL_dX",
              "frame " + std::to_string(frame) + " is outside the rollout's frames 0.." + std::to_string(frames - 1));
      gradient.push_back({frame, grid_vector(value, rows, cols, "dL_dX")});
    }
    return gradient;
  }
  const DoubleArray array = double_array(values, "dL_dX");
  require(array.ndim() == 4 && array.shape(0) == frames && array.shape(1) == rows && array.shape(2) == cols &&
              array.shape(3) == 3,
          "dL_dX",
          "expected shape " + shape_text({frames, rows, cols, 3}) + " (the positions') or a dict frame -> " +
              shape_text({rows, cols, 3}));
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(rows) * cols;
  for (int f = 0; f < frames; ++f) gradient.push_back({f, Eigen::Map<const VecX>(array.data() + f * size, size)});
  return gradient;
}

py::dict gradients(const PyRecordedRollout& r, const py::handle& dL_dX) {
  const std::vector<FrameGradient> loss = loss_gradient(r, dL_dX);
  RolloutGradient g;
  {
    py::gil_scoped_release release;
    g = backpropagate(r.record, loss);
  }
  require(
      is_complete(g.status), "rollout",
      std::string("no complete gradient (") + to_string(g.status) + ", step " + std::to_string(g.singular_step) + ")");
  const int rows = r.record.scene.grid.rows, cols = r.record.scene.grid.cols;
  const int handles = static_cast<int>(r.record.scene.handles.vertices.size());
  py::dict out;
  const auto put = [&](const char* name, const MaterialGradient& m) {
    const std::string prefix = name;
    out[py::str(prefix + "stretch")] = m.stretch;
    out[py::str(prefix + "shear")] = m.shear;
    out[py::str(prefix + "bend")] = m.bend;
    out[py::str(prefix + "density")] = m.density;
    out[py::str(prefix + "damping")] = m.damping;
  };
  put("", g.material);
  put("log_", g.log_material);
  out["gravity"] = py::array_t<double>(3, g.material.gravity.data());
  out["handle_targets"] = targets_array(g.handle_targets, handles);
  if (r.path) {
    const HandleControlPoints c = r.path->control_gradient(g.handle_targets);
    py::array_t<double> array(
        {static_cast<py::ssize_t>(handles), static_cast<py::ssize_t>(r.path->control_points()), py::ssize_t{3}});
    auto a = array.mutable_unchecked<3>();
    for (int h = 0; h < handles; ++h)
      for (int k = 0; k < r.path->control_points(); ++k)
        for (int d = 0; d < 3; ++d) a(h, k, d) = c[h][k][d];
    out["handle_path"] = array;
  }
  out["initial_positions"] = grid_array(g.initial_positions, rows, cols);
  out["initial_velocities"] = grid_array(g.initial_velocities, rows, cols);
  return out;
}

std::string recorded_repr(const PyRecordedRollout& r) {
  std::ostringstream text;
  text << "RecordedRollout(frames=" << r.record.frame_count() - 1 << ", rows=" << r.record.scene.grid.rows
       << ", cols=" << r.record.scene.grid.cols << ", optimizer='" << r.optimizer
       << "', diverged=" << (r.record.diverged ? "True" : "False") << ")";
  return text.str();
}

}  // namespace

void define_adjoint(py::module_& m) {
  py::class_<PyRecordedRollout>(m, "RecordedRollout", R"(A rollout of exact steps kept for its gradients.

Made by `record_rollout`: every step solved to a stationary point of its energy, its state and
acceleration kept, so that `gradients` runs the adjoint of any loss on the positions
(docs/design.md §15).)")
      .def_property_readonly(
          "positions",
          [](const PyRecordedRollout& r) {
            return frames_array(r.record.positions, r.record.scene.grid.rows, r.record.scene.grid.cols);
          },
          "numpy.ndarray: (frames + 1, rows, cols, 3), frame 0 the initial state.")
      .def_property_readonly(
          "rows", [](const PyRecordedRollout& r) { return r.record.scene.grid.rows; },
          "int: The grid's rows of vertices.")
      .def_property_readonly(
          "cols", [](const PyRecordedRollout& r) { return r.record.scene.grid.cols; },
          "int: The grid's columns of vertices.")
      .def_property_readonly(
          "handle_count",
          [](const PyRecordedRollout& r) { return static_cast<int>(r.record.scene.handles.vertices.size()); },
          "int: The handle vertices, the second axis of handle_targets.")
      .def_property_readonly(
          "forward_ms", [](const PyRecordedRollout& r) { return r.record.forward_ms; },
          "float: The forward pass's wall time in milliseconds.")
      .def_property_readonly(
          "diverged", [](const PyRecordedRollout& r) { return r.record.diverged; }, "bool: Whether a step diverged.")
      .def("gradients", &gradients, py::arg("dL_dX"), R"(The gradients of a loss L on the positions, by the adjoint.

Parameters
----------
dL_dX : numpy.ndarray or dict
    dL/dX shaped like `positions`, (frames + 1, rows, cols, 3), or a dict frame -> (rows, cols, 3)
    array for the frames the loss reads.

Returns
-------
dict
    By name: 'stretch', 'shear', 'bend', 'density', 'damping' (floats, dL/dk) and the same with
    'log_' (dL/dlog k), 'gravity' (3,), 'handle_targets' (steps, handles, 3) for each handle's
    target at frame s + 1, 'handle_path' (handles, K, 3) where the rollout followed a handle
    path, 'initial_positions' and 'initial_velocities' (rows, cols, 3).)")
      .def("__repr__", &recorded_repr, R"(The rollout's size, optimizer and outcome.

Returns
-------
str
    ``RecordedRollout(frames=30, rows=10, cols=10, optimizer='newton', diverged=False)``)");

  m.def("record_rollout", &record, py::arg("scene"), py::arg("optimizer") = "newton", py::arg("iters") = 0,
        py::arg("model") = py::none(), py::arg("lr") = py::none(), py::arg("initial_positions") = py::none(),
        py::arg("initial_velocities") = py::none(), py::arg("handle_targets") = py::none(),
        py::arg("handle_path") = py::none(), py::arg("path_basis") = "cubic-bspline",
        R"(Records the scene's frames for their gradients: every step exact.

Each step is solved by Newton to a tight residual, or by `optimizer` and then polished by
Newton, so that it ends at a stationary point of its energy (docs/design.md §15).

Parameters
----------
scene : Scene
    The scene, its frames included.
optimizer : str, optional
    'newton', or any optimizer of `optimizer_names` whose result Newton polishes.
iters, model, lr
    As for `Simulator`.
initial_positions, initial_velocities : array_like, optional
    (rows, cols, 3): the initial state; default the rest positions and zero.
handle_targets : array_like, optional
    (frames, handles, 3): each handle vertex's position at frames 1, 2, ...; default the scene's motion.
handle_path : array_like, optional
    (handles, K, 3): control points of offsets added to the scene's motion, zero at t = 0.
path_basis : str, optional
    The handle path's curve: 'cubic-bspline' or 'linear'.

Returns
-------
RecordedRollout
    The recorded frames, ready for `RecordedRollout.gradients`.)");
}

}  // namespace fnopt::python
