// Whole rollouts from Python: run one, read and write rollout files (HDF5, simulation/rollout_file.hpp)
// and compare trajectories (metrics/trajectory_error.hpp), with arrays shaped (frames, rows,
// cols, 3).
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/error.hpp>

#include "common.hpp"
#include "method.hpp"
#include "rollouts.hpp"

namespace fnopt::python {

PyRollout run_python_rollout(const Scene& scene, InnerOptimizer& optimizer, const RolloutOptions& options) {
  const ResolvedScene resolved = resolve(scene);
  PyRollout rollout;
  rollout.scene_text = to_scene_text(scene);
  rollout.settings = optimizer.settings();
  py::gil_scoped_release release;
  rollout.result = run_rollout(resolved, optimizer, options);
  return rollout;
}

TrajectoryFrames frames_from(const py::handle& source) {
  if (py::isinstance<PyRollout>(source)) return frames_of(source.cast<const PyRollout&>().result);
  if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__"))
    return read_trajectory_frames(py::str(source).cast<std::string>());
  throw Error("trajectory", "expected a Rollout or the path of a rollout file");
}

namespace {

py::dict step_arrays(const RolloutResult& r) {
  const std::size_t n = r.steps.size();
  py::array_t<double> wall(n), loss(n), gradient(n), strain(n), energy(n);
  py::array_t<int> iterations(n);
  py::list status;
  for (std::size_t k = 0; k < n; ++k) {
    const StepRecord& s = r.steps[k];
    wall.mutable_at(k) = s.wall_ms, loss.mutable_at(k) = s.loss, gradient.mutable_at(k) = s.gradient_norm;
    strain.mutable_at(k) = s.max_strain, energy.mutable_at(k) = s.energy, iterations.mutable_at(k) = s.iterations;
    status.append(to_string(s.status));
  }
  py::dict d;
  d["wall_ms"] = wall;
  d["loss"] = loss;
  d["gradient_norm"] = gradient;
  d["max_strain"] = strain;
  d["energy"] = energy;
  d["iterations"] = iterations;
  d["status"] = status;
  return d;
}

py::dict read_rollout(const std::string& path) {
  const TrajectoryFrames frames = read_trajectory_frames(path);
  py::dict d;
  d["positions"] = frames_array(frames.positions, frames.rows, frames.cols);
  d["times"] = py::array_t<double>(frames.times.size(), frames.times.data());
  d["rows"] = frames.rows;
  d["cols"] = frames.cols;
  // An ARCSim reference file has no scene or provenance.
  try {
    d["scene"] = read_rollout_scene(path);
    const RolloutProvenance provenance = read_rollout_provenance(path);
    d["optimizer"] = provenance.optimizer_settings;
    d["version"] = provenance.version;
    d["divergence"] = provenance.divergence;
  } catch (const Error&) {
    d["scene"] = py::none();
  }
  return d;
}

py::dict trajectory_comparison(const py::handle& reference, const py::handle& rollout, double spacing,
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
  py::dict d;
  d["e_cd"] = 1e3 * c.chamfer;
  d["e_3d"] = 1e2 * c.e3d;
  d["max_strain"] = c.max_strain;
  d["matched"] = c.describe_matching();
  return d;
}

}  // namespace

void define_rollouts(py::module_& m) {
  py::class_<PyRollout>(m, "Rollout", "A whole rollout: its frames, times and every step's record.")
      .def_property_readonly(
          "positions",
          [](const PyRollout& r) { return frames_array(r.result.positions, r.result.grid.rows, r.result.grid.cols); },
          "(frames, rows, cols, 3), frame 0 the rest state")
      .def_property_readonly(
          "times", [](const PyRollout& r) { return py::array_t<double>(r.result.times.size(), r.result.times.data()); })
      .def_property_readonly(
          "steps", [](const PyRollout& r) { return step_arrays(r.result); },
          "Per step: wall_ms, loss, gradient_norm, max_strain, energy, iterations, status")
      .def_property_readonly(
          "ms_per_frame", [](const PyRollout& r) { return ms_per_frame(r.result); },
          "Mean wall time of a step after warm-up, as compare reports it")
      .def_property_readonly("max_strain", [](const PyRollout& r) { return r.result.max_strain(); })
      .def_property_readonly("diverged", [](const PyRollout& r) { return r.result.diverged; })
      .def_property_readonly("divergence", [](const PyRollout& r) { return r.result.divergence; })
      .def_property_readonly("optimizer_settings", [](const PyRollout& r) { return r.settings; })
      .def(
          "write",
          [](const PyRollout& r, const std::string& path) {
            write_rollout_file(path, r.result, r.scene_text, r.settings);
          },
          py::arg("path"), "Writes the rollout file (HDF5) `fnopt simulate --out` writes");

  m.def(
      "run_rollout",
      [](const Scene& scene, const std::string& optimizer, int iters, const py::object& model, const py::object& lr,
         bool gd_curvature_scaled, bool warm_start) {
        const MethodRun run = method_run(scene, optimizer, iters, model, lr, gd_curvature_scaled, warm_start);
        return run_python_rollout(scene, *run.optimizer, run.options);
      },
      py::arg("scene"), py::arg("optimizer") = "pqn", py::arg("iters") = 0, py::arg("model") = py::none(),
      py::arg("lr") = py::none(), py::arg("gd_curvature_scaled") = true, py::arg("warm_start") = false,
      "The scene's frames with the optimizer, as `fnopt simulate` runs them (the same keywords as Simulator)");
  m.def("read_rollout", &read_rollout, py::arg("path"),
        "A rollout file (fnopt's or ARCSim's): dict of positions (frames, rows, cols, 3), times, rows, cols, "
        "scene (a Scene, None for ARCSim's), optimizer, version, divergence");
  m.def("compare_trajectories", &trajectory_comparison, py::arg("reference"), py::arg("rollout"),
        py::arg("spacing") = 0.0, py::arg("chamfer_samples") = 10000, py::arg("cd_stride") = 1,
        "e_CD x 10^3, e_3D x 10^2 and max strain of a rollout against a reference, each a Rollout or a "
        "rollout file; spacing: the rollout's rest edge length (taken from a Rollout)");
}

}  // namespace fnopt::python
