// fnopt validate: the training's validation score (training/rollout_validation.hpp) for any model files, so that
// checkpoints and blends are judged by the number `fnopt train --validate-res` logs, on scenes kept out of the
// tables (docs/training.md, "Choosing a model on held-out scenes").
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/rollout_validation.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/progress_bar.hpp>
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
  std::filesystem::create_directories(flags.out);

  const ValidationOptions& v = flags.validation;
  std::fprintf(stderr, "fnopt validate: %zu model(s), %s N=%d, %d frames of %s at %s against Newton%s\n", models.size(),
               v.optimizer().c_str(), v.iterations, v.frames, RolloutValidation::scene_set_text(v).c_str(),
               RolloutValidation::grid_set_text(v, true).c_str(),
               v.resolutions.size() > 1 ? " (score: the geometric mean of the grids' e_3D)" : "");
  const std::unique_ptr<RolloutValidation> validation = RolloutValidation::open(v, flags.out, "fnopt validate");

  const int steps_per_model = static_cast<int>(validation->scenes().size()) * v.frames;
  ProgressBar bar("validate", steps_per_model * static_cast<int>(models.size()));
  std::ostringstream csv;
  csv << "model," << kValidationScoreColumns << '\n';
  std::vector<ValidationScore> scores;
  for (std::size_t m = 0; m < models.size(); ++m) {
    const int done_before = static_cast<int>(m) * steps_per_model;
    scores.push_back(validation->score(models[m], [&](int done, int, const StepRecord&) {
      bar.update(done_before + done, "model " + std::to_string(m + 1) + "/" + std::to_string(models.size()));
    }));
    csv << flags.models[m] << ',';
    RolloutValidation::write_score_columns(csv, v, scores.back());
    csv << '\n';
  }
  bar.finish();
  const std::string csv_path = (std::filesystem::path(flags.out) / "validate.csv").string();
  write_text_atomically(csv_path, csv.str());

  std::printf("e_3D x 10^2 against Newton (%s N=%d, %d frames of %s)\n%-40s %10s", v.optimizer().c_str(), v.iterations,
              v.frames, RolloutValidation::scene_set_text(v).c_str(), "model", "score");
  if (v.resolutions.size() > 1)
    for (int resolution : v.resolutions) std::printf(" %9dx%d", resolution, resolution);
  std::printf(" %11s\n", "max strain");
  std::size_t best = 0;
  for (std::size_t m = 0; m < models.size(); ++m) {
    const ValidationScore& s = scores[m];
    std::printf("%-40s %10.4g", flags.models[m].c_str(), s.e3d);
    if (v.resolutions.size() > 1)
      for (std::size_t g = 0; g < v.resolutions.size(); ++g)
        std::printf(" %11.4g", g < s.grid_e3d.size() ? s.grid_e3d[g] : std::numeric_limits<double>::infinity());
    std::printf(" %10.1f%%%s\n", 100.0 * s.max_strain, s.diverged ? (" diverged: " + s.divergence).c_str() : "");
    if (s.e3d < scores[best].e3d) best = m;
  }
  std::printf("closest to Newton: %s (%.4g); table %s\n", flags.models[best].c_str(), scores[best].e3d,
              csv_path.c_str());
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
