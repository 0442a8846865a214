// Whole rollouts from Python: run one, read and write rollout files (HDF5, simulation/rollout_file.hpp)
// and compare trajectories (metrics/trajectory_error.hpp), with arrays shaped (frames, rows,
// cols, 3).
#include <sstream>

#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>

#include "common.hpp"
#include "method.hpp"
#include "rollouts.hpp"

namespace fnopt::python {

PyRollout run_python_rollout(const Scene& scene, InnerOptimizer& optimizer, const RolloutOptions& options) {
  const ResolvedScene resolved = resolve(scene);
  PyRollout rollout;
  rollout.scene = scene;
  rollout.settings = optimizer.settings();
  rollout.optimizer = optimizer.name();
  py::gil_scoped_release release;
  rollout.result = run_rollout(resolved, optimizer, options);
  return rollout;
}

py::object step_record(const StepRecord& r) {
  using namespace pybind11::literals;
  return record_type("StepRecord")(
      "wall_ms"_a = r.wall_ms, "status"_a = to_string(r.status), "iterations"_a = r.iterations,
      "evaluations"_a = r.evaluations, "gradient_evaluations"_a = r.gradient_evaluations,
      "initial_loss"_a = r.initial_loss, "loss"_a = r.loss, "initial_gradient_norm"_a = r.initial_gradient_norm,
      "gradient_norm"_a = r.gradient_norm, "max_strain"_a = r.max_strain, "energy"_a = r.energy);
}

TrajectoryFrames frames_from(const py::handle& source) {
  if (py::isinstance<PyRollout>(source)) return frames_of(source.cast<const PyRollout&>().result);
  if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__"))
    return read_trajectory_frames(py::str(source).cast<std::string>());
  throw Error("trajectory", "expected a Rollout or the path of a rollout file");
}

namespace {

py::object read_rollout(const std::string& path) {
  using namespace pybind11::literals;
  const TrajectoryFrames frames = read_trajectory_frames(path);
  py::object scene = py::none(), optimizer = py::none(), version = py::none(), divergence = py::none();
  // An ARCSim reference file has no scene or provenance.
  try {
    scene = py::cast(read_rollout_scene(path));
    const RolloutProvenance provenance = read_rollout_provenance(path);
    optimizer = py::str(provenance.optimizer_settings);
    version = py::str(provenance.version);
    divergence = py::str(provenance.divergence);
  } catch (const Error&) {
    scene = optimizer = version = divergence = py::none();
  }
  return record_type("RolloutFile")("positions"_a = frames_array(frames.positions, frames.rows, frames.cols),
                                    "times"_a = py::array_t<double>(frames.times.size(), frames.times.data()),
                                    "rows"_a = frames.rows, "cols"_a = frames.cols, "scene"_a = scene,
                                    "optimizer"_a = optimizer, "version"_a = version, "divergence"_a = divergence);
}

py::object trajectory_comparison(const py::handle& reference, const py::handle& rollout, double spacing,
                                 int chamfer_samples, int cd_stride) {
  const TrajectoryFrames ref = frames_from(reference), run = frames_from(rollout);
  TrajectoryComparisonOptions options;
  options.chamfer.samples = chamfer_samples;
  options.chamfer.validate();
  require(cd_stride >= 1, "cd_stride", "must be at least 1");
  options.chamfer_stride = cd_stride;
  if (spacing <= 0.0 && py::isinstance<PyRollout>(rollout))
    spacing = rollout.cast<const PyRollout&>().result.grid.spacing;
  TrajectoryComparison c;
  {
    py::gil_scoped_release release;
    c = compare_trajectories(ref, run, spacing, options);
  }
  using namespace pybind11::literals;
  return record_type("Comparison")("e_cd"_a = 1e3 * c.chamfer, "e_3d"_a = 1e2 * c.e3d, "max_strain"_a = c.max_strain,
                                   "matched"_a = c.describe_matching());
}

std::string rollout_repr(const PyRollout& r) {
  std::ostringstream text;
  text << "Rollout(frames=" << r.result.positions.size() - 1 << ", rows=" << r.result.grid.rows
       << ", cols=" << r.result.grid.cols << ", optimizer='" << r.optimizer
       << "', diverged=" << (r.result.diverged ? "True" : "False") << ")";
  return text.str();
}

}  // namespace

void define_rollouts(py::module_& m) {
  py::class_<PyRollout>(m, "Rollout", R"(A whole rollout: its frames, times and every step's record.

Made by `run_rollout`; `write` stores it as ``fnopt simulate --out`` does.)")
      .def_property_readonly(
          "positions",
          [](const PyRollout& r) { return frames_array(r.result.positions, r.result.grid.rows, r.result.grid.cols); },
          "numpy.ndarray: (frames + 1, rows, cols, 3), frame 0 the rest state.")
      .def_property_readonly(
          "times", [](const PyRollout& r) { return py::array_t<double>(r.result.times.size(), r.result.times.data()); },
          "numpy.ndarray: (frames + 1,), each frame's time in seconds.")
      .def_property_readonly(
          "steps",
          [](const PyRollout& r) {
            py::list steps;
            for (const StepRecord& step : r.result.steps) steps.append(step_record(step));
            return steps;
          },
          "list of StepRecord: Every step's record, in order.")
      .def_property_readonly(
          "scene", [](const PyRollout& r) { return r.scene; }, "Scene: The scene it ran, as its file stores it.")
      .def_property_readonly(
          "rows", [](const PyRollout& r) { return r.result.grid.rows; }, "int: The grid's rows of vertices.")
      .def_property_readonly(
          "cols", [](const PyRollout& r) { return r.result.grid.cols; }, "int: The grid's columns of vertices.")
      .def_property_readonly(
          "ms_per_frame", [](const PyRollout& r) { return ms_per_frame(r.result); },
          "float: Mean wall time of a step after warm-up, as compare reports it.")
      .def_property_readonly(
          "max_strain", [](const PyRollout& r) { return r.result.max_strain(); },
          "float: The largest edge strain over all frames.")
      .def_property_readonly(
          "diverged", [](const PyRollout& r) { return r.result.diverged; }, "bool: Whether a step diverged.")
      .def_property_readonly(
          "divergence", [](const PyRollout& r) { return r.result.divergence; },
          "str: Why it diverged, empty if it did not.")
      .def_property_readonly(
          "optimizer", [](const PyRollout& r) { return r.optimizer; }, "str: The optimizer's name.")
      .def_property_readonly(
          "optimizer_settings", [](const PyRollout& r) { return r.settings; },
          "str: The optimizer and its settings, as the rollout file stores them.")
      .def(
          "write",
          [](const PyRollout& r, const std::string& path) { write_rollout_file(path, r.result, r.scene, r.settings); },
          py::arg("path"), R"(Writes the rollout file (HDF5) that ``fnopt simulate --out`` writes.

Parameters
----------
path : str
    The file to write.

Returns
-------
None)")
      .def("__repr__", &rollout_repr, R"(The rollout's size, optimizer and outcome.

Returns
-------
str
    ``Rollout(frames=390, rows=32, cols=32, optimizer='pqn', diverged=False)``)");

  m.def(
      "run_rollout",
      [](const Scene& scene, const std::string& optimizer, int iters, const py::object& model, const py::object& lr,
         bool gd_curvature_scaled, bool warm_start) {
        const MethodRun run = method_run(scene, optimizer, iters, model, lr, gd_curvature_scaled, warm_start);
        return run_python_rollout(scene, *run.optimizer, run.options);
      },
      py::arg("scene"), py::arg("optimizer") = "pqn", py::arg("iters") = 0, py::arg("model") = py::none(),
      py::arg("lr") = py::none(), py::arg("gd_curvature_scaled") = true, py::arg("warm_start") = false,
      R"(Runs the scene's frames, as ``fnopt simulate`` does.

Parameters
----------
scene : Scene
    The scene, its frames included.
optimizer, iters, model, lr, gd_curvature_scaled, warm_start
    As for `Simulator`.

Returns
-------
Rollout
    The frames and every step's record.)");
  m.def("read_rollout", &read_rollout, py::arg("path"), R"(Reads a rollout file, fnopt's or ARCSim's.

Parameters
----------
path : str
    The HDF5 rollout file.

Returns
-------
RolloutFile
    Its positions (float32 as stored), times, grid, and for fnopt's files the scene,
    optimizer settings, version and divergence.)");
  m.def("compare_trajectories", &trajectory_comparison, py::arg("reference"), py::arg("rollout"),
        py::arg("spacing") = 0.0, py::arg("chamfer_samples") = 10000, py::arg("cd_stride") = 1,
        R"(Measures a rollout against a reference trajectory, frames matched by time.

Parameters
----------
reference, rollout : Rollout or str or os.PathLike
    Each a Rollout or a rollout file.
spacing : float, optional
    The rollout's rest edge length, for its strain; taken from a Rollout when 0.
chamfer_samples : int, optional
    Points sampled on each mesh for e_CD.
cd_stride : int, optional
    e_CD on every k-th matched frame only (e_3D uses all).

Returns
-------
Comparison
    e_CD x 10^3, e_3D x 10^2, the rollout's max strain and how the frames matched.)");
}

}  // namespace fnopt::python
