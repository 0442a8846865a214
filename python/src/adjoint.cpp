// Gradients through rollouts from Python (docs/design.md §15): fnopt.record_rollout records a
// rollout of exact steps (adjoint/recorded_rollout.hpp), RecordedRollout.gradients runs the
// backward pass of a loss given by its dL/dX (adjoint/rollout_adjoint.hpp) and returns the
// gradients by name as NumPy arrays and floats; RecordedRollout.chamfer_loss and
// fnopt.sample_surface give e_CD as such a loss (adjoint/rollout_loss.hpp).
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <sstream>

#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>
#include <fnopt/adjoint/rollout_loss.hpp>
#include <fnopt/cloth/grid.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>

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

// The backward pass's verdict (gradient_verdict.hpp) and each kind's radius (GradientVerdict::radius).
py::dict verdict_dict(const RolloutGradient& g) {
  const GradientVerdict& v = g.verdict;
  py::dict out, valid_below;
  out["conditioning"] = to_string(v.conditioning);
  out["start_radius"] = v.start_radius;
  out["loss_radius"] = v.loss_radius;
  out["binding_frame"] = v.binding_frame;
  out["growth"] = std::exp(v.log_growth);
  out["precision"] = v.precision;
  const MaterialGradient& m = g.log_material;
  for (const auto& [name, value] : {std::pair{"stretch", m.stretch}, {"shear", m.shear}, {"bend", m.bend},
                                    {"density", m.density}, {"damping", m.damping}})
    valid_below[name] = v.radius(std::abs(value));
  valid_below["gravity"] = v.radius(m.gravity.norm());
  double targets = 0.0;
  for (const auto& step : g.handle_targets)
    for (const Vec3& t : step) targets += t.squaredNorm();
  valid_below["handle_targets"] = v.radius(std::sqrt(targets));
  valid_below["initial_positions"] = v.radius(g.initial_positions.norm());
  valid_below["initial_velocities"] = v.radius(g.initial_velocities.norm());
  out["valid_below"] = valid_below;
  return out;
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
  out["status"] = to_string(g.status);
  out["verdict"] = verdict_dict(g);
  return out;
}

// (P, 3) points, any P >= 1.
std::vector<Vec3> observed_points(const py::handle& values, const std::string& field) {
  const DoubleArray array = double_array(values, field.c_str());
  require(array.ndim() == 2 && array.shape(0) >= 1 && array.shape(1) == 3, field, "expected shape (P, 3), P >= 1");
  return point_list(array, static_cast<std::size_t>(array.shape(0)), field.c_str());
}

ChamferOptions chamfer_options(int samples, std::uint64_t seed) {
  ChamferOptions options;
  options.samples = samples;
  options.seed = seed;
  with_flag_names({{"cd-samples", "samples"}}, [&] { options.validate(); });
  return options;
}

// e_CD of the rollout's frames against observed points (adjoint/rollout_loss.hpp's
// surface_chamfer_loss) and its dL/dX by frame, ready for gradients().
py::tuple chamfer_loss(const PyRecordedRollout& r, const py::dict& observed, int samples, std::uint64_t seed) {
  const ChamferOptions options = chamfer_options(samples, seed);
  std::vector<FramePoints> frames;
  for (const auto& item : observed) {
    const int frame = item.first.cast<int>();
    frames.push_back({frame, observed_points(item.second, "observed[" + std::to_string(frame) + "]")});
  }
  const RolloutLoss loss = surface_chamfer_loss(r.record, frames, options);
  py::dict gradient;
  for (const FrameGradient& g : loss.gradient)
    gradient[py::int_(g.frame)] = grid_array(g.gradient, r.record.scene.grid.rows, r.record.scene.grid.cols);
  return py::make_tuple(loss.value, gradient);
}

// e_CD's points on a grid mesh (metrics/chamfer.hpp): `samples` points by area, the fixed seed.
py::array_t<double> sample_surface(const py::handle& positions, int samples, std::uint64_t seed) {
  const DoubleArray array = double_array(positions, "positions");
  require(array.ndim() == 3 && array.shape(0) >= 2 && array.shape(1) >= 2 && array.shape(2) == 3, "positions",
          "expected shape (rows, cols, 3), rows and cols at least 2");
  Grid grid;
  grid.rows = static_cast<int>(array.shape(0));
  grid.cols = static_cast<int>(array.shape(1));
  const ChamferOptions options = chamfer_options(samples, seed);
  return point_array(sample_mesh_surface(grid_vector(array, grid.rows, grid.cols, "positions"), grid.triangles(),
                                         options.samples, options.seed));
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
    path, 'initial_positions' and 'initial_velocities' (rows, cols, 3), 'status', and 'verdict',
    a dict saying how far the gradient holds (docs/api.md, docs/design.md §15).)")
      .def("chamfer_loss", &chamfer_loss, py::arg("observed"), py::arg("samples") = 10000,
           py::arg("seed") = ChamferOptions{}.seed, R"(e_CD of the rollout against observed points, and its dL/dX.

The mean over the given frames of the Chamfer distance (squared, both directions) between
`samples` points sampled by area on the cloth's triangles and the observed points: against
`sample_surface` of another mesh with the same samples and seed, the e_CD that `evaluate`
reports (not x 10^3). The gradient holds each sample's triangle and nearest neighbours fixed
(docs/design.md §15).

Parameters
----------
observed : dict
    Frame -> (P, 3) array of observed points at that frame (frame 0 the initial state).
samples : int, optional
    Points sampled on the cloth per frame.
seed : int, optional
    The sampling seed (e_CD's fixed one by default).

Returns
-------
tuple
    (loss, dL_dX): the loss in m^2 and a dict frame -> (rows, cols, 3) array for `gradients`.)")
      .def("__repr__", &recorded_repr, R"(The rollout's size, optimizer and outcome.

Returns
-------
str
    ``RecordedRollout(frames=30, rows=10, cols=10, optimizer='newton', diverged=False)``)");

  m.def("sample_surface", &sample_surface, py::arg("positions"), py::arg("samples") = 10000,
        py::arg("seed") = ChamferOptions{}.seed, R"(Points sampled by area on a grid mesh, as e_CD samples it.

Parameters
----------
positions : numpy.ndarray
    (rows, cols, 3) vertex positions of a grid cloth (a frame of a rollout, or of an ARCSim run).
samples : int, optional
    How many points.
seed : int, optional
    The sampling seed (e_CD's fixed one by default).

Returns
-------
numpy.ndarray
    (samples, 3) points, for `RecordedRollout.chamfer_loss`'s observed frames.)");
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
