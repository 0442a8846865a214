#include "app/optimizer_flags.hpp"

#include <fnopt/baselines/newton.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt::app {

std::string newton_budget_text() {
  return "default " + std::to_string(NewtonOptimizer::reference_solve_options().max_iterations) +
         ", to a residual acceleration of " + NewtonOptimizer::reference_stop_text();
}

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice) {
  command.add_option("--optimizer", choice.name, "inner optimizer: " + optimizer_names())->capture_default_str();
  command
      .add_option("--iters", choice.iterations,
                  "iterations per time step (default 10; newton: at most this many, " + newton_budget_text() + ")")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            int value = 0;
            return parse_int(text, value) && value >= 1 ? ""
                                                        : "must be a positive iteration budget, got '" + text + "'";
          },
          "N >= 1"));
  command.add_option("--tolerance", choice.tolerance,
                     "newton, newton-min: the residual acceleration each step stops at, in m/s^2 (default " +
                         NewtonOptimizer::reference_stop_text() + "; smaller for data to fit to, as 1e-8)");
  command.add_option("--lr", choice.learning_rate,
                     "learning rate: gd in units of 1/lambda_max of the mass-scaled Hessian (default 1), adam in "
                     "cell widths per step^2 per iteration (default 0.003)");
  add_method_setting_flags(command, choice);
}

void add_method_setting_flags(CLI::App& command, OptimizerChoice& choice) {
  command.add_option("--model", choice.model,
                     "learned optimizer weights (default: models/fnopt-multires.pt for fnopt-ss, the 32^2-only "
                     "models/fnopt-32.pt for the other learned methods)");
  command
      .add_option("--pqn-history", choice.pqn_history,
                  "pqn and fnopt-pqn: curvature pairs kept (0: plain -A^-1 g steps)")
      ->capture_default_str();
}

}  // namespace fnopt::app
