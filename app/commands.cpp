#include "app/commands.hpp"

namespace fnopt::app {

std::vector<CommandFactory>& command_registry() {
  static std::vector<CommandFactory> registry;
  return registry;
}

}  // namespace fnopt::app
