// fnopt.Simulator: a rollout one step at a time (simulation/simulator.hpp) with NumPy arrays in
// and out, for closed-loop control and for optimizers written in Python.
#include <pybind11/stl.h>

#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/simulator.hpp>
#include <fnopt/util/error.hpp>

#include "common.hpp"
#include "method.hpp"
#include "step_problem.hpp"

namespace fnopt::python {
namespace {

py::dict record_dict(const StepRecord& r) {
  py::dict d;
  d["wall_ms"] = r.wall_ms;
  d["status"] = to_string(r.status);
  d["iterations"] = r.iterations;
  d["initial_loss"] = r.initial_loss;
  d["loss"] = r.loss;
  d["initial_gradient_norm"] = r.initial_gradient_norm;
  d["gradient_norm"] = r.gradient_norm;
  d["max_strain"] = r.max_strain;
  d["energy"] = r.energy;
  return d;
}

class PySimulator {
 public:
  PySimulator(const Scene& scene, const std::string& optimizer, int iters, const py::object& model,
              const py::object& lr, bool gd_curvature_scaled, bool warm_start)
      : resolved_(resolve(scene)) {
    MethodRun run = method_run(scene, optimizer, iters, model, lr, gd_curvature_scaled, warm_start);
    optimizer_ = std::move(run.optimizer);
    simulator_ = std::make_unique<Simulator>(resolved_, *optimizer_, run.options);
  }

  py::array_t<double> step(const py::object& handles, const py::object& acceleration) {
    const std::vector<Vec3> targets = targets_of(handles);
    end_problem();
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
  py::object last_step() const {
    return simulator_->steps_done() == 0 && !simulator_->diverged() ? py::object(py::none())
                                                                    : py::object(record_dict(last_));
  }
  int rows() const { return resolved_.grid.rows; }
  int cols() const { return resolved_.grid.cols; }
  const Simulator& simulator() const { return *simulator_; }
  const Scene& scene() const { return resolved_.scene; }
  std::string settings() const { return optimizer_->settings(); }

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

}  // namespace

void define_simulator(py::module_& m) {
  py::class_<PySimulator>(m, "Simulator", R"(A rollout one step at a time, from rest.

optimizer: a name of `fnopt --help` (pqn, newton, fnopt-ss, gd, ...); iters: its budget per
step (0: the method's default); model: the learned optimizer's weights (default: the shipped
model); lr: gd's or adam's learning rate; gd_curvature_scaled: gd's lr in units of
1/lambda_max (True, as on the command line) or a fixed step along inverse_metric * g (False).
Positions, velocities and accelerations are arrays shaped (rows, cols, 3).)")
      .def(py::init<const Scene&, const std::string&, int, const py::object&, const py::object&, bool, bool>(),
           py::arg("scene"), py::arg("optimizer") = "pqn", py::arg("iters") = 0, py::arg("model") = py::none(),
           py::arg("lr") = py::none(), py::arg("gd_curvature_scaled") = true, py::arg("warm_start") = false)
      .def("step", &PySimulator::step, py::arg("handles") = py::none(), py::arg("acceleration") = py::none(),
           R"(One time step; returns the new positions. handles: this step's handle positions, (H, 3) in the
order of handle_vertices (default: the scene's motion). acceleration: the step's answer from an
optimizer of one's own instead of the built-in one (its handle entries are ignored).)")
      .def("rollout", &PySimulator::rollout, py::arg("frames"),
           "`frames` steps along the scene's motion; returns (frames + 1, rows, cols, 3), the current state first "
           "(double precision; a rollout file stores float32)")
      .def("problem", &PySimulator::problem, py::arg("handles") = py::none(),
           "The next step's StepProblem (handles as in step), valid until the state moves")
      .def(
          "energy", [](PySimulator& s, const py::handle& a) { return s.problem(py::none()).energy(a); }, py::arg("a"),
          "L(a) of the next step (the scene's motion)")
      .def(
          "gradient", [](PySimulator& s, const py::handle& a) { return s.problem(py::none()).gradient(a); },
          py::arg("a"), "grad L(a) of the next step, zero at the handles")
      .def(
          "hessian",
          [](PySimulator& s, const py::handle& a, bool project) { return s.problem(py::none()).hessian(a, project); },
          py::arg("a"), py::arg("project") = false, "hess L(a) of the next step (SciPy sparse)")
      .def("set_state", &PySimulator::set_state, py::arg("positions"), py::arg("velocities"),
           py::arg("steps") = py::none(),
           "Sets the state; `steps`: the steps done, so that time = steps * dt (default: unchanged)")
      .def_property_readonly("positions", &PySimulator::positions)
      .def_property_readonly("velocities", &PySimulator::velocities)
      .def_property_readonly("time", [](const PySimulator& s) { return s.simulator().time(); })
      .def_property_readonly("steps_done", [](const PySimulator& s) { return s.simulator().steps_done(); })
      .def_property_readonly("diverged", [](const PySimulator& s) { return s.simulator().diverged(); })
      .def_property_readonly("divergence", [](const PySimulator& s) { return s.simulator().divergence(); })
      .def_property_readonly("handle_vertices", &PySimulator::handle_vertices, "(H, 2): (row, column) of each handle")
      .def("trajectory_targets", &PySimulator::trajectory_targets, py::arg("t"),
           "(H, 3): the handles' positions the scene's motion prescribes at time t")
      .def_property_readonly(
          "last_step", &PySimulator::last_step,
          "The last step's record (wall_ms, status, iterations, loss, max_strain, ...), None before one")
      .def_property_readonly("scene", &PySimulator::scene)
      .def_property_readonly("optimizer_settings", &PySimulator::settings)
      .def_property_readonly("rows", &PySimulator::rows)
      .def_property_readonly("cols", &PySimulator::cols);
}

}  // namespace fnopt::python
