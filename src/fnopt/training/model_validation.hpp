#pragma once
// `fnopt validate`: the training's validation score (rollout_validation.hpp) for any model files, so
// that checkpoints and blends are judged by the number `fnopt train --validate-res` logs, on scenes
// kept out of the tables (docs/training.md, "Choosing a model on held-out scenes").
#include <string>
#include <vector>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/training/rollout_validation.hpp>

namespace fnopt {

// Scores each model (models[m] read from model_paths[m]) against the Newton references solved
// once into `out` (a directory), with a progress bar; writes out/validate.csv and prints the table
// and the closest model.
void run_model_validation(const std::vector<FNO2d>& models, const std::vector<std::string>& model_paths,
                          const ValidationOptions& options, const std::string& out);

}  // namespace fnopt
