#pragma once
// Subcommand registration: each app/*_command.cpp adds its CLI11 subcommand and callback.
#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace fnopt::app {

using CommandFactory = std::function<void(CLI::App&)>;

std::vector<CommandFactory>& command_registry();

// Registers a subcommand at static-initialisation time.
struct RegisterCommand {
  explicit RegisterCommand(CommandFactory factory) { command_registry().push_back(std::move(factory)); }
};

}  // namespace fnopt::app
