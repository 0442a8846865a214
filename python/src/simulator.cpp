// fnopt.Simulator: a rollout one step at a time (simulation/simulator.hpp) with NumPy arrays in
// and out, for closed-loop control and for optimizers written in Python.
#include <pybind11/stl.h>

#include <sstream>

#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/simulator.hpp>
#include <fnopt/util/error.hpp>

#include "common.hpp"
#include "method.hpp"
#include "rollouts.hpp"
#include "step_problem.hpp"

namespace fnopt::python {
namespace {

class PySimulator {
 public:
  PySimulator(const Scene& scene, const std::string& optimizer, int iters, const py::object& model,
              const py::object& lr, bool gd_curvature_scaled, bool warm_start)
      : resolved_(resolve(scene)) {
    MethodRun run = method_run(scene, optimizer, iters, model, lr, gd_curvature_scaled, warm_start);
    optimizer_ = std::move(run.optimizer);
    simulator_ = std::make_unique<Simulator>(resolved_, *optimizer_, run.options);
  }

  py::array_t<double> step(const py::object& handles, const py::object& acceleration, const py::object& obstacles) {
    const std::vector<Vec3> targets = targets_of(handles);
    end_problem();
    if (!obstacles.is_none())
      simulator_->set_obstacle_offsets(point_list(obstacles, resolved_.scene.obstacles.size(), "obstacles"));
    if (acceleration.is_none()) {
      py::gil_scoped_release release;
      last_ = simulator_->step(targets);
    } else {
      VecX start;
      simulator_->prepare_step(start, targets);
      last_ = simulator_->commit(grid_vector(acceleration, rows(), cols(), "acceleration"));
    }
    require(!simulator_->diverged(), "simulation", simulator_->divergence());
    return positions();
  }

  py::array_t<double> rollout(int frames) {
    require(frames >= 0, "frames", "must be zero or more");
    end_problem();
    std::vector<VecX> kept{simulator_->positions()};
    {
      py::gil_scoped_release release;
      for (int k = 0; k < frames && !simulator_->diverged(); ++k) {
        last_ = simulator_->step();
        if (!simulator_->diverged()) kept.push_back(simulator_->positions());
      }
    }
    if (simulator_->diverged())
      PyErr_WarnEx(PyExc_RuntimeWarning,
                   ("fnopt: " + simulator_->divergence() + "; the frames before it are returned").c_str(), 1);
    return frames_array(kept, rows(), cols());
  }

  StepProblemView problem(const py::object& handles) {
    end_problem();
    VecX start;
    StepProblem& problem = simulator_->prepare_step(start, targets_of(handles));
    return StepProblemView(problem, start, alive_);
  }

  void set_state(const py::handle& x, const py::handle& v, std::optional<int> steps) {
    end_problem();
    simulator_->set_state(grid_vector(x, rows(), cols(), "positions"), grid_vector(v, rows(), cols(), "velocities"),
                          steps);
  }

  py::array_t<double> positions() const { return grid_array(simulator_->positions(), rows(), cols()); }
  py::array_t<double> velocities() const { return grid_array(simulator_->velocities(), rows(), cols()); }
  py::array_t<int> handle_vertices() const {
    const std::vector<int>& vertices = simulator_->handle_vertices();
    py::array_t<int> ij({static_cast<py::ssize_t>(vertices.size()), py::ssize_t{2}});
    auto out = ij.mutable_unchecked<2>();
    for (std::size_t h = 0; h < vertices.size(); ++h)
      out(h, 0) = vertices[h] / cols(), out(h, 1) = vertices[h] % cols();
    return ij;
  }
  py::array_t<double> trajectory_targets(double t) const { return point_array(simulator_->trajectory_targets(t)); }
  py::array_t<double> obstacle_offsets() const { return point_array(simulator_->obstacle_offsets()); }
  py::object last_step() const {
    return simulator_->steps_done() == 0 && !simulator_->diverged() ? py::object(py::none()) : step_record(last_);
  }
  int rows() const { return resolved_.grid.rows; }
  int cols() const { return resolved_.grid.cols; }
  const Simulator& simulator() const { return *simulator_; }
  const Scene& scene() const { return resolved_.scene; }
  std::string settings() const { return optimizer_->settings(); }
  std::string repr() const {
    std::ostringstream text;
    text << "Simulator(rows=" << rows() << ", cols=" << cols() << ", optimizer='" << optimizer_->name()
         << "', steps_done=" << simulator_->steps_done() << ", time=" << simulator_->time()
         << ", diverged=" << (simulator_->diverged() ? "True" : "False") << ")";
    return text.str();
  }

 private:
  std::vector<Vec3> targets_of(const py::object& handles) const {
    if (handles.is_none()) return simulator_->trajectory_targets(simulator_->time() + resolved_.scene.dt);
    return point_list(handles, simulator_->handle_vertices().size(), "handles");
  }
  // The problem handed out last is over once the state moves or a new one is prepared.
  void end_problem() {
    *alive_ = false;
    alive_ = std::make_shared<bool>(true);
  }

  ResolvedScene resolved_;
  std::unique_ptr<InnerOptimizer> optimizer_;
  std::unique_ptr<Simulator> simulator_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  StepRecord last_;
};

// The simulator's state, set and read, and what it runs.
void define_simulator_state(py::class_<PySimulator>& simulator) {
  simulator
      .def("set_state", &PySimulator::set_state, py::arg("positions"), py::arg("velocities"),
           py::arg("steps") = py::none(), R"(Sets the cloth's state.

Parameters
----------
positions, velocities : array_like
    (rows, cols, 3).
steps : int, optional
    The steps done, so that time = steps * dt; default: unchanged.

Returns
-------
None)")
      .def_property_readonly("positions", &PySimulator::positions, "numpy.ndarray: The positions, (rows, cols, 3).")
      .def_property_readonly("velocities", &PySimulator::velocities, "numpy.ndarray: The velocities, (rows, cols, 3).")
      .def_property_readonly(
          "time", [](const PySimulator& s) { return s.simulator().time(); }, "float: The time in seconds.")
      .def_property_readonly(
          "steps_done", [](const PySimulator& s) { return s.simulator().steps_done(); }, "int: The steps taken.")
      .def_property_readonly(
          "diverged", [](const PySimulator& s) { return s.simulator().diverged(); },
          "bool: Whether a step diverged (every later step raises).")
      .def_property_readonly(
          "divergence", [](const PySimulator& s) { return s.simulator().divergence(); },
          "str: Why it diverged, empty if it did not.")
      .def_property_readonly("handle_vertices", &PySimulator::handle_vertices,
                             "numpy.ndarray: (H, 2), the (row, column) of each handle.")
      .def("trajectory_targets", &PySimulator::trajectory_targets, py::arg("t"),
           R"(Where the scene's motion puts the handles.

Parameters
----------
t : float
    A time in seconds.

Returns
-------
numpy.ndarray
    (H, 3), in the order of `handle_vertices`.)")
      .def_property_readonly("obstacle_offsets", &PySimulator::obstacle_offsets,
                             "numpy.ndarray: (K, 3), each obstacle's translation from its rest pose now: its "
                             "motion's, or where the last step steered it.")
      .def_property_readonly("last_step", &PySimulator::last_step,
                             "StepRecord or None: The last step's record; None before the first step.")
      .def_property_readonly("scene", &PySimulator::scene, "Scene: The scene it runs.")
      .def_property_readonly("optimizer_settings", &PySimulator::settings,
                             "str: The optimizer and its settings, as a rollout file stores them.")
      .def_property_readonly("rows", &PySimulator::rows, "int: The grid's rows of vertices.")
      .def_property_readonly("cols", &PySimulator::cols, "int: The grid's columns of vertices.")
      .def("__repr__", &PySimulator::repr, R"(The grid, optimizer and progress.

Returns
-------
str
    ``Simulator(rows=8, cols=8, optimizer='pqn', steps_done=3, time=0.05, diverged=False)``)");
}

}  // namespace

void define_simulator(py::module_& m) {
  py::class_<PySimulator> simulator(m, "Simulator", R"(A rollout one step at a time, from rest.

Positions, velocities and accelerations are float64 arrays shaped (rows, cols, 3).

Parameters
----------
scene : Scene
    The scene to run.
optimizer : str, optional
    An optimizer's name (`optimizer_names`: pqn, newton, fnopt-ss, gd, ...).
iters : int, optional
    Its budget per step; 0: the method's default.
model : str or os.PathLike, optional
    The learned optimizer's weights; default: the method's shipped model.
lr : float, optional
    gd's or adam's learning rate; default: the method's.
gd_curvature_scaled : bool, optional
    gd's lr in units of 1/lambda_max (True, as on the command line) or a fixed step along
    inverse_metric * g (False).
warm_start : bool, optional
    Start each step from the previous step's acceleration instead of a_0.)");
  simulator
      .def(py::init<const Scene&, const std::string&, int, const py::object&, const py::object&, bool, bool>(),
           py::arg("scene"), py::arg("optimizer") = "pqn", py::arg("iters") = 0, py::arg("model") = py::none(),
           py::arg("lr") = py::none(), py::arg("gd_curvature_scaled") = true, py::arg("warm_start") = false)
      .def("step", &PySimulator::step, py::arg("handles") = py::none(), py::arg("acceleration") = py::none(),
           py::arg("obstacles") = py::none(), R"(Takes one time step.

Parameters
----------
handles : array_like, optional
    This step's handle positions, (H, 3) in the order of `handle_vertices`; default: where
    the scene's motion puts them.
acceleration : array_like, optional
    The step's answer, (rows, cols, 3), from an optimizer of one's own instead of the built-in
    one (its handle entries are ignored).
obstacles : array_like, optional
    Steers the obstacles: their translations from their rest poses at the step's end, (K, 3)
    in the scene's order, instead of their motions' (the next step starts from there); default:
    their motions.

Returns
-------
numpy.ndarray
    The new positions, (rows, cols, 3).)")
      .def("rollout", &PySimulator::rollout, py::arg("frames"), R"(Steps along the scene's motion.

A divergence stops it with a RuntimeWarning.

Parameters
----------
frames : int
    The steps to take.

Returns
-------
numpy.ndarray
    (frames + 1, rows, cols, 3) in double precision, the current state first (a rollout file
    stores float32).)")
      .def("problem", &PySimulator::problem, py::arg("handles") = py::none(), R"(The next step's problem.

Parameters
----------
handles : array_like, optional
    The step's handle positions, as in `step`.

Returns
-------
StepProblem
    Valid until the state moves.)")
      .def(
          "energy", [](PySimulator& s, const py::handle& a) { return s.problem(py::none()).energy(a); }, py::arg("a"),
          R"(The next step's objective, the handles on the scene's motion.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3).

Returns
-------
float
    L(a).)")
      .def(
          "gradient", [](PySimulator& s, const py::handle& a) { return s.problem(py::none()).gradient(a); },
          py::arg("a"), R"(The next step's gradient, the handles on the scene's motion.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3).

Returns
-------
numpy.ndarray
    grad L(a), (rows, cols, 3), zero at the handles.)")
      .def(
          "hessian",
          [](PySimulator& s, const py::handle& a, bool project) { return s.problem(py::none()).hessian(a, project); },
          py::arg("a"), py::arg("project") = false, R"(The next step's Hessian, the handles on the scene's motion.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3).
project : bool, optional
    Project each stencil's block to positive semi-definite.

Returns
-------
scipy.sparse.csc_matrix
    hess L(a) over all 3 rows cols dofs, the identity on the handles'.)");
  define_simulator_state(simulator);
}

}  // namespace fnopt::python
