// fnopt validate: flags only; the scores are training/model_validation.hpp (the training's validation
// score for any model files, docs/training.md, "Choosing a model on held-out scenes").
#include <string>
#include <vector>

#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/model_validation.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include "app/commands.hpp"
#include "app/threads.hpp"
#include "app/validation_flags.hpp"

namespace fnopt::app {
namespace {

struct ValidateFlags {
  std::vector<std::string> models;
  std::string out;
  ValidationOptions validation;
  int threads = 0;
};

void run_validate(ValidateFlags& flags) {
  auto flag_names = ValidationOptions::flag_names("");
  flag_names.emplace("validate.pqn_direction", "pqn-direction");
  with_flag_names(flag_names, [&] { flags.validation.validate(); });
  std::vector<FNO2d> models;  // every file checked before the references are solved
  for (const std::string& path : flags.models) models.push_back(load_learned_model(path));
  set_thread_count(flags.threads);
  run_model_validation(models, flags.models, flags.validation, flags.out);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<ValidateFlags>();
  CLI::App* command = app.add_subcommand(
      "validate", "score learned models by the training's validation: rollouts of held-out scenes against Newton");
  command->add_option("MODEL", flags->models, "model files (checkpoints, blends) to score")->required();
  command
      ->add_option("--out", flags->out,
                   "directory of the Newton references (solved once, cached; a training's OUT reuses its references) "
                   "and validate.csv")
      ->required();
  command
      ->add_option("--res", flags->validation.resolutions,
                   "N x N grid(s), comma-separated; the score is the mean e_3D over each grid's scenes (with several "
                   "grids, the geometric mean of the grids' means). At 32^2 every motion with the corner handles is "
                   "a scene of the 32^2 table: validate there off the corners (e.g. --handles diagonal)")
      ->delimiter(',')
      ->capture_default_str();
  add_validation_scene_flags(*command, flags->validation, "");
  command->add_flag("--pqn-direction", flags->validation.pqn_direction,
                    "score with fnopt's rule (pqn's direction in the subspace), for models trained for it");
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_validate(*flags); });
});

}  // namespace
}  // namespace fnopt::app
