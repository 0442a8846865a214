#pragma once
// Minimisation of a loss in a box, l <= x <= u, by a projected Levenberg-Marquardt iteration on a
// Gauss-Newton model (Nocedal & Wright 2006, §10.3; the damping update of Nielsen 1999): for the few
// variables of a material fit (docs/design.md §15), on any callable that returns the loss, its
// gradient g and a positive semidefinite model G of its Hessian (J^T W J for a least-squares loss).
//
// Per iteration: the variables at a bound whose gradient points out of the box are held; on the
// others the step solves (G + mu (max diag G) I) d = -g (Levenberg's damping), the trial is the
// projection P(x + d), and it is kept if it lowers the loss, when mu shrinks by
// max(1/10, 1 - (2 r - 1)^3) (Nielsen's rule, whose floor is 1/3), r the actual over the model's
// decrease; else mu grows (x2, x4, x8, ...). The stop says why:
//  * Stationary: the undamped Gauss-Newton step moves no free variable by more than
//    step_tolerance (the model's minimum is where the iterate is), or the projected gradient is zero;
//  * Settled (only with decrease_tolerance > 0): the undamped Gauss-Newton step's model decrease,
//    -(g.s + s.G s / 2), is below decrease_tolerance of the loss: the model sees little left to gain,
//    as at a noise floor (a shorter horizon's fit that only has to reach a basin stops there);
//  * NoDecrease: mu passed max_damping without a trial that lowers the loss (the loss is rough at
//    the scale of the solver's precision there, or the model is wrong);
//  * EvaluationBudget: max_evaluations used.
#include <functional>

#include <Eigen/Core>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct BoundedGaussNewtonParams {
  int max_evaluations = 30;      // calls of the objective at most
  double step_tolerance = 1e-6;  // Stationary: the Gauss-Newton step's largest free coordinate
  double decrease_tolerance = 0.0;  // Settled: its model decrease over the loss (0: never)
  double initial_damping = 1e-3; // mu at the start, relative to the largest diagonal of G
  double max_damping = 1e8;      // NoDecrease beyond it
  // The first trial moves no variable by more than this (0: no limit): the model knows the step's
  // size only once it has seen the loss's curvature.
  double first_step = 0.0;
  // No trial moves a variable by more than this (0: no limit): where the loss barely sees a
  // variable the model's step along it is long, and the model is a local one.
  double max_step = 0.0;

  void validate() const;  // throws Error naming the field
};

enum class BoundedGaussNewtonStatus { Stationary, Settled, NoDecrease, EvaluationBudget, NonFinite };
const char* to_string(BoundedGaussNewtonStatus status);

struct BoundedGaussNewtonResult {
  VecX x;              // the best point evaluated
  double value = 0.0;  // the loss there
  VecX gradient;       // and its gradient
  Eigen::MatrixXd model;          // and G
  BoundedGaussNewtonStatus status = BoundedGaussNewtonStatus::EvaluationBudget;
  int iterations = 0;   // accepted steps
  int evaluations = 0;  // calls of the objective
};

// f(x), writing its gradient and G.
using GaussNewtonObjective = std::function<double(const VecX& x, VecX& gradient, Eigen::MatrixXd& model)>;

// Minimises f from x0 (projected into the box first). Throws Error("bounds", ...) for bounds of the
// wrong size or with l > u somewhere.
BoundedGaussNewtonResult minimize_by_gauss_newton(const GaussNewtonObjective& f, const VecX& x0, const VecX& lower,
                                                  const VecX& upper, const BoundedGaussNewtonParams& params = {});

}  // namespace fnopt
