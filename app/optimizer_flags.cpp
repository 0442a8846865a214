#include "app/optimizer_flags.hpp"

#include "baselines/newton.hpp"
#include "util/error.hpp"

namespace fnopt::app {

std::string optimizer_names() { return "newton"; }

std::unique_ptr<InnerOptimizer> OptimizerChoice::make() const {
  require(iterations >= 0, "iters", "must be a positive iteration budget");
  if (name == "newton") return std::make_unique<NewtonOptimizer>();
  throw Error("optimizer: unknown optimizer '" + name + "' (choose from: " + optimizer_names() + ")");
}

InnerSolveOptions OptimizerChoice::solve_options() const {
  if (name == "newton") {
    InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
    if (iterations > 0) options.max_iterations = iterations;
    return options;
  }
  return {iterations > 0 ? iterations : 10, 0.0};
}

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice) {
  command.add_option("--optimizer", choice.name, "inner optimizer: " + optimizer_names())->capture_default_str();
  command.add_option("--iters", choice.iterations,
                     "iterations per time step (newton: at most this many, default 100 to ||g|| <= 1e-9 ||g0||)");
  command.add_option("--lr", choice.learning_rate, "learning rate of gd/adam");
  command.add_option("--model", choice.model, "learned optimizer weights file");
}

}  // namespace fnopt::app
