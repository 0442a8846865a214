#include "step_problem.hpp"

#include <pybind11/eigen.h>

#include <sstream>
#include <vector>

#include <fnopt/baselines/first_order.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt::python {

StepProblemView::StepProblemView(StepProblem& problem, const VecX& start, std::shared_ptr<const bool> alive)
    : problem_(&problem),
      rows_(problem.grid().rows),
      cols_(problem.grid().cols),
      start_(start),
      inverse_metric_(ClothSmoothProblem(problem).inverse_metric()),
      handle_count_(static_cast<int>(problem.dirichlet().fixed_vertices().size())),
      dt_(problem.objective().dt()),
      alive_(std::move(alive)) {}

void StepProblemView::check_alive() const {
  require(*alive_, "problem", "its time step is over: take the problem of the current step");
}

VecX StepProblemView::vector_of(const py::handle& a) const {
  check_alive();
  return grid_vector(a, rows_, cols_, "acceleration");
}

double StepProblemView::energy(const py::handle& a) const { return problem_->value(vector_of(a)); }

py::array_t<double> StepProblemView::gradient(const py::handle& a) const {
  VecX g;
  problem_->value_gradient(vector_of(a), g);
  return grid_array(g, rows_, cols_);
}

py::tuple StepProblemView::energy_gradient(const py::handle& a) const {
  VecX g;
  const double value = problem_->value_gradient(vector_of(a), g);
  return py::make_tuple(value, grid_array(g, rows_, cols_));
}

double StepProblemView::residual_acceleration(const py::handle& a) const {
  VecX g;
  problem_->value_gradient(vector_of(a), g);
  return problem_->objective().residual_acceleration(g);
}

Eigen::SparseMatrix<double> StepProblemView::hessian(const py::handle& a, bool project) const {
  const VecX values = vector_of(a);
  const std::vector<int>& free_index = problem_->dirichlet().free_index();
  const Eigen::SparseMatrix<double>& free = problem_->objective().hessian(values, free_index, project);
  // Free dof f -> its dof in the whole vector.
  std::vector<int> dof_of(free.rows());
  for (int v = 0; v < static_cast<int>(free_index.size()); ++v)
    if (free_index[v] >= 0)
      for (int d = 0; d < 3; ++d) dof_of[3 * free_index[v] + d] = 3 * v + d;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(free.nonZeros() + 3 * problem_->dirichlet().fixed_vertices().size());
  for (int col = 0; col < free.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(free, col); it; ++it)
      entries.emplace_back(dof_of[it.row()], dof_of[it.col()], it.value());
  for (int v : problem_->dirichlet().fixed_vertices())
    for (int d = 0; d < 3; ++d) entries.emplace_back(3 * v + d, 3 * v + d, 1.0);
  const Eigen::Index size = values.size();
  Eigen::SparseMatrix<double> full(size, size);
  full.setFromTriplets(entries.begin(), entries.end());
  return full;
}

py::array_t<bool> StepProblemView::free_mask() const {
  py::array_t<bool> mask({rows_, cols_});
  bool* out = mask.mutable_data();
  const std::vector<int>& free_index = problem_->dirichlet().free_index();
  for (std::size_t v = 0; v < free_index.size(); ++v) out[v] = free_index[v] >= 0;
  return mask;
}

py::array_t<double> StepProblemView::positions() const {
  check_alive();
  return grid_array(problem_->objective().start_positions(), rows_, cols_);
}

py::array_t<double> StepProblemView::velocities() const {
  check_alive();
  return grid_array(problem_->objective().start_velocities(), rows_, cols_);
}

std::string StepProblemView::repr() const {
  std::ostringstream text;
  text << "StepProblem(rows=" << rows_ << ", cols=" << cols_ << ", dt=" << dt_ << ", handles=" << handle_count_
       << ", valid=" << (*alive_ ? "True" : "False") << ")";
  return text.str();
}

void define_step_problem(py::module_& m) {
  py::class_<StepProblemView>(m, "StepProblem",
                              R"(One time step's problem: minimise the backward-Euler objective L(a) over the
next step's accelerations a, shaped (rows, cols, 3), with the handles' entries prescribed.

Valid while its step lasts (`Simulator.problem`, or one call of an optimizer written in
Python); afterwards every call raises fnopt.Error.)")
      .def("energy", &StepProblemView::energy, py::arg("a"), R"(The objective.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3) or flat.

Returns
-------
float
    L(a).)")
      .def("gradient", &StepProblemView::gradient, py::arg("a"), R"(The objective's gradient.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3) or flat.

Returns
-------
numpy.ndarray
    grad L(a), (rows, cols, 3), zero at the handles.)")
      .def("energy_gradient", &StepProblemView::energy_gradient, py::arg("a"),
           R"(The objective and its gradient at once.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3) or flat.

Returns
-------
tuple of (float, numpy.ndarray)
    L(a) and grad L(a).)")
      .def("hessian", &StepProblemView::hessian, py::arg("a"), py::arg("project") = false,
           R"(The objective's Hessian over all 3 rows cols dofs.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3) or flat.
project : bool, optional
    Project each stencil's block to positive semi-definite.

Returns
-------
scipy.sparse.csc_matrix
    hess L(a), the identity on the handles' dofs, so that a Newton step with the gradient
    leaves the handles where they are.)")
      .def("residual_acceleration", &StepProblemView::residual_acceleration, py::arg("a"),
           R"(The unbalanced force per mass.

Parameters
----------
a : array_like
    Accelerations, (rows, cols, 3) or flat.

Returns
-------
float
    max_i |g_i| / (m_i dt^2) in m/s^2: 0 at the solution.)")
      .def_property_readonly("start", &StepProblemView::start,
                             "numpy.ndarray: a_0, 0 on the free dofs and the handles' prescription.")
      .def_property_readonly(
          "inverse_metric", &StepProblemView::inverse_metric,
          "numpy.ndarray: 1 / (dt^2 m_i) per dof: a first-order step is a -= lr * inverse_metric * g.")
      .def_property_readonly("free_mask", &StepProblemView::free_mask,
                             "numpy.ndarray: (rows, cols) booleans, True where a vertex is free.")
      .def_property_readonly("positions", &StepProblemView::positions,
                             "numpy.ndarray: x_t, the state the step starts from, (rows, cols, 3).")
      .def_property_readonly("velocities", &StepProblemView::velocities, "numpy.ndarray: v_t, (rows, cols, 3).")
      .def_property_readonly("rows", &StepProblemView::rows, "int: The grid's rows of vertices.")
      .def_property_readonly("cols", &StepProblemView::cols, "int: The grid's columns of vertices.")
      .def_property_readonly("dt", &StepProblemView::dt, "float: The time step in seconds.")
      .def_property_readonly("valid", &StepProblemView::valid, "bool: Whether its step still lasts.")
      .def("__repr__", &StepProblemView::repr, R"(The grid, time step, handles and whether it is still valid.

Returns
-------
str
    ``StepProblem(rows=8, cols=8, dt=0.0166667, handles=2, valid=True)``)");
}

}  // namespace fnopt::python
