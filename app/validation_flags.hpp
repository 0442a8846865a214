#pragma once
// The validation scenes' flags, shared by `fnopt train` (prefix "validate-", each needing --validate-res) and
// `fnopt validate` (no prefix): one definition, so both commands score a model alike (rollout_validation.hpp).
#include <CLI/CLI.hpp>
#include <string>

#include <fnopt/training/rollout_validation.hpp>

namespace fnopt::app {

// --PREFIXframes, --PREFIXmotions, --PREFIXhandles, --PREFIXiters, --PREFIXsubspace; each `needs` `required` if given.
void add_validation_scene_flags(CLI::App& command, ValidationOptions& options, const std::string& prefix,
                                CLI::Option* required = nullptr);

}  // namespace fnopt::app
