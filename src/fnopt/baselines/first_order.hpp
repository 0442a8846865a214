#pragma once
// What the classical first-order methods (GD, Adam, L-BFGS) see of a problem, so that the same
// code runs on a cloth time step and on the analytic test problems (quadratics, Rosenbrock).
//
// Units. The cloth objective's gradient is dt^2 (M a + grad P): with dt = 1/60 and vertex
// masses of 1e-4 kg it is a tiny number whose scale changes with the resolution (m ~ h^2).
// The methods therefore work in the metric P = dt^2 M (the Hessian of the inertia term): their
// raw direction is the preconditioned gradient P^-1 g, which has units of an acceleration
// [m/s^2] and is the exact backward-Euler step when there is no elastic energy. Parameters
// that are step sizes are then dimensionless (GD) or in grid units h/dt^2 (Adam), see each
// method. For the analytic problems P = I and the step unit is 1.
#include <optional>
#include <vector>

#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/optimizer/step_problem.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt {

class SmoothProblem {
 public:
  virtual ~SmoothProblem() = default;
  virtual double value(const VecX& x) = 0;
  // Writes the gradient (zero on fixed dofs) and returns the value.
  virtual double value_gradient(const VecX& x, VecX& gradient) = 0;
  // 1 / diag(P), per dof: the methods move along -inverse_metric .* g.
  virtual const VecX& inverse_metric() const = 0;
  // A natural step length [units of x], h/dt^2 for the cloth (one cell width per step^2).
  virtual double step_unit() const = 0;
  // The cloth time step behind the problem, for methods that build matrices from its energy;
  // null for the analytic problems.
  virtual StepProblem* step_problem() const { return nullptr; }
  // The first trial step of a line search from x along `direction` that keeps every vertex outside
  // the obstacles (StepProblem::feasible_step); `step` where nothing constrains it.
  virtual double feasible_step(const VecX&, const VecX&, double step) { return step; }
};

// A cloth time step seen as a SmoothProblem: inverse metric 1/(dt^2 m_i), step unit h/dt^2.
// Holds references: `problem` must outlive it.
class ClothSmoothProblem final : public SmoothProblem {
 public:
  explicit ClothSmoothProblem(StepProblem& problem);
  double value(const VecX& a) override { return problem_->value(a); }
  double value_gradient(const VecX& a, VecX& gradient) override { return problem_->value_gradient(a, gradient); }
  const VecX& inverse_metric() const override { return inverse_metric_; }
  double step_unit() const override { return step_unit_; }
  StepProblem* step_problem() const override { return problem_; }
  double feasible_step(const VecX& a, const VecX& direction, double step) override {
    return problem_->feasible_step(a, direction, step);
  }

 private:
  StepProblem* problem_;
  VecX inverse_metric_;
  double step_unit_;
};

// A caller-defined problem with P = I (or a given inverse metric), for tests and tools.
template <class Function>
class FunctionSmoothProblem final : public SmoothProblem {
 public:
  // Function: double(const VecX& x, VecX* gradient_or_null).
  FunctionSmoothProblem(int size, Function function, double step_unit = 1.0)
      : function_(std::move(function)), inverse_metric_(VecX::Ones(size)), step_unit_(step_unit) {}
  double value(const VecX& x) override {
    ++evaluations;
    return function_(x, nullptr);
  }
  double value_gradient(const VecX& x, VecX& gradient) override {
    ++evaluations;
    gradient.resize(x.size());
    return function_(x, &gradient);
  }
  const VecX& inverse_metric() const override { return inverse_metric_; }
  double step_unit() const override { return step_unit_; }
  long evaluations = 0;

 private:
  Function function_;
  VecX inverse_metric_;
  double step_unit_;
};

// Base of the classical methods: the InnerOptimizer calls on a cloth step are forwarded to
// begin()/step() on a ClothSmoothProblem view, built once per StepProblem and kept. Tests and
// tools call begin()/step() directly on any SmoothProblem.
class FirstOrderOptimizer : public InnerOptimizer {
 public:
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) final;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) final;

  // Starts a new minimisation at x (value and gradient given): resets the per-step state.
  virtual void begin(SmoothProblem& problem, const VecX& x, double value, const VecX& gradient) = 0;
  // One iteration: moves x and leaves value and gradient at the new iterate, or returns a stop.
  virtual std::optional<SolveStatus> step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) = 0;

 protected:
  // Called before begin() when the cloth step belongs to a different objective than the last
  // one (a new scene, grid or time step size): forget anything learnt about the old one.
  virtual void on_new_problem() {}

 private:
  std::optional<ClothSmoothProblem> cloth_;
  const StepProblem* cloth_problem_ = nullptr;
  const BackwardEulerObjective* cloth_objective_ = nullptr;
  int cloth_dofs_ = 0;
  double cloth_dt_ = 0.0;
};

// The largest eigenvalue of P^-1 H at x (H = the Hessian of the problem), by `iterations` steps
// of power iteration on Hessian-vector products from finite differences of gradients (one
// gradient evaluation per step; `gradient` is the gradient at x). A lower bound that converges
// from below; the fixed dofs drop out after the first step (their gradient is zero). Returns
// at least 1e-12.
double estimate_max_curvature(SmoothProblem& problem, const VecX& x, const VecX& gradient, int iterations);

}  // namespace fnopt
