#pragma once
// fnopt.StepProblem: one time step's problem as an optimizer written in Python sees it (the
// backward-Euler objective L(a) of the next step, handles eliminated), valid while its step
// lasts: a Simulator's step before it is taken, or one call of a Python inner optimizer.
#include <Eigen/SparseCore>

#include <memory>
#include <string>

#include <fnopt/optimizer/step_problem.hpp>

#include "common.hpp"

namespace fnopt::python {

class StepProblemView {
 public:
  // `alive` is false once the step is over; every call then raises.
  StepProblemView(StepProblem& problem, const VecX& start, std::shared_ptr<const bool> alive);

  double energy(const py::handle& a) const;
  // The gradient with its handle entries zeroed (what every fnopt optimizer sees).
  py::array_t<double> gradient(const py::handle& a) const;
  py::tuple energy_gradient(const py::handle& a) const;
  // The Hessian on every dof, handle rows and columns replaced by the identity, so that a Newton
  // step with the masked gradient leaves the handles where they are. `project`: each stencil's
  // block projected to positive semi-definite.
  Eigen::SparseMatrix<double> hessian(const py::handle& a, bool project) const;
  // max_i |g_i| / (m_i dt^2) [m/s^2]: the unbalanced force per mass; 0 at the solution.
  double residual_acceleration(const py::handle& a) const;
  py::array_t<double> start() const { return grid_array(start_, rows_, cols_); }
  // 1 / (dt^2 m_i) per dof: the first-order methods' step along -g (the inertia term's Newton step).
  py::array_t<double> inverse_metric() const { return grid_array(inverse_metric_, rows_, cols_); }
  // (rows, cols) booleans: true where the vertex is free, false at a handle.
  py::array_t<bool> free_mask() const;
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double dt() const { return dt_; }
  // The state the step starts from, (rows, cols, 3).
  py::array_t<double> positions() const;
  py::array_t<double> velocities() const;
  bool valid() const { return *alive_; }
  std::string repr() const;

 private:
  VecX vector_of(const py::handle& a) const;
  void check_alive() const;

  StepProblem* problem_;
  int rows_, cols_;
  VecX start_, inverse_metric_;
  int handle_count_;
  double dt_;
  std::shared_ptr<const bool> alive_;
};

}  // namespace fnopt::python
