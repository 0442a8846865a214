#include "app/validation_flags.hpp"

namespace fnopt::app {

void add_validation_scene_flags(CLI::App& command, ValidationOptions& options, const std::string& prefix,
                                CLI::Option* required) {
  auto add = [&](CLI::Option* option) {
    option->capture_default_str();
    if (required) option->needs(required);
  };
  add(command.add_option("--" + prefix + "frames", options.frames, "time steps of each validation rollout"));
  add(command
          .add_option("--" + prefix + "motions", options.motions,
                      "motions of the validation scenes, comma-separated (default xyz_v4,rot_h1: not xy_v2, rot_h0 or "
                      "xyz_v3, the test scenes of the 64^2 and 100^2 tables in docs/results.md); the score is the "
                      "mean e_3D over every motion with every handle preset")
          ->delimiter(','));
  add(command
          .add_option("--" + prefix + "handles", options.handles,
                      "handle presets of the validation scenes, comma-separated (e.g. corner,diagonal,single-center "
                      "to validate off the corners too)")
          ->delimiter(','));
  add(command.add_option("--" + prefix + "iters", options.iterations, "iterations per validation step"));
  add(command.add_option("--" + prefix + "subspace", options.subspace,
                         "proposals the validation's subspace step keeps (fnopt-ss); 0 validates with fnopt-ls, as "
                         "the validations before fnopt-ss did"));
}

}  // namespace fnopt::app
