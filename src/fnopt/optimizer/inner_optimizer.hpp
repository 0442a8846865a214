#pragma once
// One interface for every inner optimizer, classical and learned (docs/design.md §4, §6): the
// rollout loop, its timing and its metrics are written once, in solve_step() and rollout.hpp.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fnopt/optimizer/solve_status.hpp>
#include <fnopt/optimizer/step_problem.hpp>

namespace fnopt {

class InnerOptimizer {
 public:
  virtual ~InnerOptimizer() = default;

  virtual std::string name() const = 0;
  // A one-line description of the settings, stored with every rollout.
  virtual std::string settings() const = 0;
  // Starts a time step at iterate a with value L(a) and masked gradient g. Classical methods
  // reset their history here; a learned optimizer may carry state across steps.
  virtual void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) = 0;
  // One iteration: moves a (free dofs only) and leaves value and gradient at the new iterate.
  // Returns a status to stop early (e.g. LineSearchFailed), or nothing to go on.
  virtual std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) = 0;
  // Called where the solve's tolerance is met: a method that seeks a local minimum rather than any
  // stationary point may move a off a saddle there (and return true: the solve goes on). Default:
  // a stationary point is where the solve ends.
  virtual bool leave_stationary_point(StepProblem&, VecX&, double&, VecX&) { return false; }
  // Whether iterate() moves only along paths the no-penetration filter has passed (a method that
  // cuts its own trials to their feasible fraction, StepProblem::feasible_fraction): solve_step then
  // does not check the move again. Default: solve_step filters every iterate (docs/design.md §14).
  virtual bool filters_its_iterates() const { return false; }
};

struct InnerSolveOptions {
  int max_iterations = 10;          // the iteration budget N per time step
  double relative_tolerance = 0.0;  // stop at ||g|| <= tol ||g_0||; 0 runs the whole budget
  // Stop once the residual acceleration max_i |g_i| / (m_i dt^2), in m/s^2, is at most this (the
  // part of a = f(x)/m the step leaves unbalanced: BackwardEulerObjective::residual_acceleration).
  double acceleration_tolerance = 0.0;
  // Whether the solve stops at a tolerance (else it runs its budget).
  bool to_tolerance() const { return relative_tolerance > 0.0 || acceleration_tolerance > 0.0; }
};

struct InnerSolveResult {
  SolveStatus status = SolveStatus::IterationBudget;
  int iterations = 0;
  double initial_value = 0.0;
  double value = 0.0;
  double initial_gradient_norm = 0.0;
  double gradient_norm = 0.0;
  std::vector<double> gradient_norms;  // ||g|| at every iterate, ||g_0|| first
};

// Runs one time step: iterates from a until the tolerance, the budget or a stop status.
InnerSolveResult solve_step(InnerOptimizer& optimizer, StepProblem& problem, VecX& a, const InnerSolveOptions& options);

}  // namespace fnopt
