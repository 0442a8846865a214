#pragma once
// The flags that choose an inner optimizer (methods/registry.hpp): --optimizer, --iters, --lr and
// the per-method settings, shared by simulate, evaluate, compare and stability.
#include <CLI/CLI.hpp>

#include <fnopt/methods/registry.hpp>

namespace fnopt::app {

void add_optimizer_flags(CLI::App& command, OptimizerChoice& choice);
// The settings of particular methods (--model, --pqn-history, --pqn-matrix), for commands
// that choose the methods themselves (compare).
void add_method_setting_flags(CLI::App& command, OptimizerChoice& choice);

}  // namespace fnopt::app
