#include <fnopt/training/model_validation.hpp>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

// The table: each model's score (and each grid's, with several) and its largest strain.
void print_scores(const std::vector<std::string>& model_paths, const ValidationOptions& v,
                  const std::vector<ValidationScore>& scores, const std::string& csv_path) {
  std::printf("e_3D x 10^2 against Newton (%s N=%d, %d frames of %s)\n%-40s %10s", v.optimizer().c_str(), v.iterations,
              v.frames, RolloutValidation::scene_set_text(v).c_str(), "model", "score");
  if (v.resolutions.size() > 1)
    for (int resolution : v.resolutions) std::printf(" %9dx%d", resolution, resolution);
  std::printf(" %11s\n", "max strain");
  std::size_t best = 0;
  for (std::size_t m = 0; m < scores.size(); ++m) {
    const ValidationScore& s = scores[m];
    std::printf("%-40s %10.4g", model_paths[m].c_str(), s.e3d);
    if (v.resolutions.size() > 1)
      for (std::size_t g = 0; g < v.resolutions.size(); ++g)
        std::printf(" %11.4g", g < s.grid_e3d.size() ? s.grid_e3d[g] : std::numeric_limits<double>::infinity());
    std::printf(" %10.1f%%%s\n", 100.0 * s.max_strain, s.diverged ? (" diverged: " + s.divergence).c_str() : "");
    if (s.e3d < scores[best].e3d) best = m;
  }
  std::printf("closest to Newton: %s (%.4g); table %s\n", model_paths[best].c_str(), scores[best].e3d,
              csv_path.c_str());
}

}  // namespace

void run_model_validation(const std::vector<FNO2d>& models, const std::vector<std::string>& model_paths,
                          const ValidationOptions& options, const std::string& out) {
  std::filesystem::create_directories(out);
  const ValidationOptions& v = options;
  std::fprintf(stderr, "fnopt validate: %zu model(s), %s N=%d, %d frames of %s at %s against Newton%s\n", models.size(),
               v.optimizer().c_str(), v.iterations, v.frames, RolloutValidation::scene_set_text(v).c_str(),
               RolloutValidation::grid_set_text(v, true).c_str(),
               v.resolutions.size() > 1 ? " (score: the geometric mean of the grids' e_3D)" : "");
  const std::unique_ptr<RolloutValidation> validation = RolloutValidation::open(v, out, "fnopt validate");

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
    csv << model_paths[m] << ',';
    RolloutValidation::write_score_columns(csv, v, scores.back());
    csv << '\n';
  }
  bar.finish();
  const std::string csv_path = (std::filesystem::path(out) / "validate.csv").string();
  write_text_atomically(csv_path, csv.str());

  print_scores(model_paths, v, scores, csv_path);
}

}  // namespace fnopt
