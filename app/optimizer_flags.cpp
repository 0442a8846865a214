#include "app/optimizer_flags.hpp"

#include <functional>
#include <vector>

#include "baselines/adam.hpp"
#include "baselines/gradient_descent.hpp"
#include "baselines/lbfgs.hpp"
#include "baselines/newton.hpp"
#include "optimizer/learned/learned_optimizer.hpp"
#include "util/error.hpp"
#include "util/parse_text.hpp"

namespace fnopt::app {
namespace {

// One entry per optimizer name: how to build it from the flags. To add a method, add a row.
struct OptimizerEntry {
  const char* name;
  std::function<std::unique_ptr<InnerOptimizer>(const OptimizerChoice&)> make;
};

const std::vector<OptimizerEntry>& optimizer_table() {
  static const std::vector<OptimizerEntry> table = {
      {"newton", [](const OptimizerChoice&) { return std::make_unique<NewtonOptimizer>(); }},
      {"fnopt",
       [](const OptimizerChoice& c) {
         return std::make_unique<LearnedOptimizer>(c.model.empty() ? shipped_model_path() : c.model);
       }},
      {"gd",
       [](const OptimizerChoice& c) {
         GradientDescentParams params;
         if (c.learning_rate > 0.0) params.learning_rate = c.learning_rate;
         return std::make_unique<GradientDescentOptimizer>(params);
       }},
      {"adam",
       [](const OptimizerChoice& c) {
         AdamParams params;
         if (c.learning_rate > 0.0) params.learning_rate = c.learning_rate;
         return std::make_unique<AdamOptimizer>(params);
       }},
      {"lbfgs",
       [](const OptimizerChoice&) {
         LbfgsParams params;
         params.line_search = false;
         return std::make_unique<LbfgsOptimizer>(params);
       }},
      {"lbfgs-ls",
       [](const OptimizerChoice&) {
         LbfgsParams params;
         params.line_search = true;
         return std::make_unique<LbfgsOptimizer>(params);
       }},
  };
  return table;
}

}  // namespace

std::string shipped_model_path() { return std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt"; }

std::string optimizer_names() {
  std::vector<std::string> names;
  for (const auto& entry : optimizer_table()) names.push_back(entry.name);
  return joined(names);
}

std::unique_ptr<InnerOptimizer> OptimizerChoice::make() const {
  require(iterations >= 0, "iters", "must be a positive iteration budget");
  require(learning_rate >= 0.0, "lr", "must be positive");
  for (const auto& entry : optimizer_table())
    if (name == entry.name) return entry.make(*this);
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
                     "iterations per time step (default 10; newton: at most this many, default 300 to "
                     "||g|| <= 1e-9 ||g0||)");
  command.add_option("--lr", choice.learning_rate,
                     "learning rate: gd in units of 1/lambda_max of the mass-scaled Hessian (default 1), adam in "
                     "cell widths per step^2 per iteration (default 0.003)");
  command.add_option("--model", choice.model, "learned optimizer weights (default: the shipped models/fnopt-32.pt)");
}

}  // namespace fnopt::app
