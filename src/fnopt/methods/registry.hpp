#pragma once
// Every inner optimizer by name (a polysolve-style factory), with the traits that commands and
// studies need instead of comparing names: how its work per step is set, whether it is the
// reference, whether it takes a learning rate, its default budgets and its relative cost.
#include <memory>
#include <string>
#include <vector>

#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>

namespace fnopt {

// How a method's work per time step is set.
enum class BudgetKind {
  Iterations,   // N iterations per step (--iters)
  ToTolerance,  // to its tolerance; an N, where given, caps the iterations (newton)
  OneSolve,     // one solve per step, no budget (implicit-euler)
};

// What the commands need to know of a method without comparing its name.
struct MethodTraits {
  BudgetKind budget = BudgetKind::Iterations;
  bool reference = false;       // defines the exact step that every error is measured against
  bool learning_rate = false;   // takes --lr (compare sweeps it)
  double iteration_cost = 1.0;  // relative cost of one iteration, for progress ETAs only
  int suite_budget = 100;       // iterations per step in the stability suite (0: to tolerance)
  bool learned = false;         // runs a trained model (--model): the super-resolution study's subject
  bool ablation = false;        // a variant kept for the studies that take a method apart, listed apart
};

// Throws Error("optimizer", "...") for an unknown name.
MethodTraits method_traits(const std::string& name);

// Relative cost of one frame, for the ETAs of progress bars only (compare, stability): one
// L-BFGS iteration at 32^2 is 1; cost grows with the grid's vertices, a converged Newton step
// as (vertices/1024)^1.3 (sparse factorizations); METHOD-interpK iterates on its coarse grid.
double frame_cost(const std::string& method, int iterations, bool converged, int vertices);
// An interpolation-ablation method (METHOD-interpK).
bool is_interpolated_method(const std::string& name);

struct OptimizerChoice {
  // pqn, the fastest method for its error on one CPU thread at every grid measured (on compare's
  // error-time frontier, docs/design.md §8).
  std::string name = "pqn";
  int iterations = 0;          // budget per step; 0 = the method's default
  double learning_rate = 0.0;  // 0 = the method's default
  // A method that solves to a tolerance (newton, newton-min): the residual acceleration it stops at
  // [m/s^2]; 0 = the reference's (NewtonOptimizer::reference_solve_options()).
  double tolerance = 0.0;
  std::string model;           // learned optimizer weights
  int pqn_history = PqnParams{}.history;
  // gd's learning rate in units of 1/lambda_max(P^-1 H) (true, the command line's) or of the
  // inertia step P^-1 g (false: a fixed step, as one would write gradient descent by hand).
  bool gd_curvature_scaled = GradientDescentParams{}.curvature_scaled;

  // Throws Error("optimizer", "...") for an unknown name or invalid settings.
  std::unique_ptr<InnerOptimizer> make() const;
  // Budget and tolerance: Newton runs to its reference tolerance, the others their budget.
  InnerSolveOptions solve_options() const;
  // Throws Error("optimizer", "...") if the method cannot run on a rows x cols grid (a coarse
  // grid of METHOD-interpK that is not coarser).
  void check_grid(int rows, int cols) const;
};

// Every optimizer's registry name (the ablations too, if asked), in the registry's order.
std::vector<std::string> optimizer_list(bool ablations = true);
// The names for help texts: the methods, then "; ablations: " and the ablation variants.
std::string optimizer_names();
// The method whose traits say it is the reference (newton): every error is measured against it.
std::string reference_method();
// The model trained at 32^2 only (models/fnopt-32.pt): the zero-shot super-resolution study's, and the
// default of --model for every learned method but fnopt-ss.
std::string shipped_model_path();
// fnopt-ss's default model (models/fnopt-multires.pt): the 32^2 model blended with its continuation on a
// pool of 32^2, 64^2 and 100^2 grids (docs/training.md, "The multi-resolution model").
std::string multires_model_path();

}  // namespace fnopt
