#pragma once
// Choosing an inner optimizer by name (polysolve style factory): the flags --optimizer,
// --iters, --lr, --model shared by simulate, compare and stability.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "optimizer/inner_optimizer.hpp"
#include "optimizer/rollout.hpp"

namespace fnopt::app {

struct OptimizerChoice {
  // The learned optimizer on the shipped model, with the subspace step over its last eight
  // proposals (measured against the secant step fnopt-ls: e_CD x 10^3 0.681 -> 0.344 over the
  // fifteen 32^2 motions, 33.2 -> 9.41 at 100^2 on xy_v2, for 2-10 % more time; README
  // "Results").
  std::string name = "fnopt-ss";
  int iterations = 0;           // budget per step; 0 = the method's default
  double learning_rate = 0.0;   // 0 = the method's default
  std::string model;            // learned optimizer weights

  // Throws Error("optimizer: ...") for an unknown name or invalid settings.
  std::unique_ptr<InnerOptimizer> make() const;
  // Budget and tolerance: Newton runs to its reference tolerance, the others their budget.
  InnerSolveOptions solve_options() const;
};

std::string optimizer_names();  // "newton" ... for help texts
// The trained model shipped in the repository (models/fnopt-32.pt), the default of --model.
std::string shipped_model_path();

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice);

}  // namespace fnopt::app
