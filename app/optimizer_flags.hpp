#pragma once
// The flags that choose an inner optimizer (methods/registry.hpp): --optimizer, --iters, --lr and
// the per-method settings, shared by simulate, evaluate, compare and stability.
#include <CLI/CLI.hpp>

#include <fnopt/methods/registry.hpp>

namespace fnopt::app {

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice);
// The settings of particular methods (--model, --pqn-history), for commands
// that choose the methods themselves (compare).
void add_method_setting_flags(CLI::App& command, OptimizerChoice& choice);
// "default 1000, to a residual acceleration of 0.1 m/s^2": the reference's budget and stop,
// for help texts.
std::string newton_budget_text();

}  // namespace fnopt::app
