// Validation rollouts: the Newton reference is solved once and reused only for its own scene,
// every motion runs with every handle preset on every grid, several grids score the geometric mean of
// their means, scores are deterministic and leave the model alone,
// and a trained model scores better than an untrained one.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/training/rollout_validation.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

ValidationOptions small_validation() {
  ValidationOptions v;
  v.resolutions = {12};
  v.frames = 20;
  v.motions = {"xy_v2"};
  return v;
}

FNO2d tiny_model() {
  torch::manual_seed(3);
  return FNO2d(
      FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4));
}

TEST(RolloutValidation, SolvesEachReferenceOnceAndOnlyReusesItForItsOwnScene) {
  const testing::TempDir tmp;
  const auto& dir = tmp.path();
  int steps_reported = 0, last_total = 0;
  auto count = [&](int done, int total, const StepRecord&) {
    ++steps_reported;
    EXPECT_EQ(done, steps_reported);
    last_total = total;
  };
  ValidationOptions two = small_validation();
  two.motions = {"xy_v2", "rot_h0"};
  RolloutValidation first(two, dir.string(), count);
  EXPECT_EQ(first.references_solved(), 2);
  EXPECT_EQ(steps_reported, 40);
  EXPECT_EQ(last_total, 40);
  ASSERT_EQ(first.scenes().size(), 2u);
  EXPECT_EQ(first.scenes()[1].motion, "rot_h0");
  steps_reported = 0;
  RolloutValidation again(two, dir.string(), count);
  EXPECT_EQ(again.references_solved(), 0);
  EXPECT_EQ(steps_reported, 0);
  // A file of the same name holding another scene (here: a Newton rollout of another motion
  // copied over it) is solved anew, not compared against the wrong frames.
  std::filesystem::copy_file(RolloutValidation::reference_file(dir.string(), two, 12, "rot_h0"),
                             RolloutValidation::reference_file(dir.string(), two, 12, "xy_v2"),
                             std::filesystem::copy_options::overwrite_existing);
  RolloutValidation changed(two, dir.string(), count);
  EXPECT_EQ(changed.references_solved(), 1);
  EXPECT_EQ(steps_reported, 20);
  // The right scene solved by another solver (its settings differ) is solved anew too.
  const std::string path = RolloutValidation::reference_file(dir.string(), two, 12, "xy_v2");
  NewtonOptimizer newton;
  const RolloutResult other = run_rollout(resolve(changed.scenes()[0]), newton, {});
  write_rollout_file(path, other, to_scene_text(changed.scenes()[0]), "newton: other settings");
  RolloutValidation resolved(two, dir.string());
  EXPECT_EQ(resolved.references_solved(), 1);
}

TEST(RolloutValidation, ValidatesEveryMotionWithEveryHandlePreset) {
  const testing::TempDir tmp;
  const auto& dir = tmp.path();
  ValidationOptions v = small_validation();
  v.handles = {"corner", "diagonal"};
  EXPECT_EQ(RolloutValidation::scene_set_text(v), "xy_v2@corner+diagonal");
  EXPECT_EQ(RolloutValidation::scene_set_text(small_validation()), "xy_v2");
  // Corner scenes keep the file names of the caches written before presets could be chosen.
  const std::string corner = RolloutValidation::reference_file(dir.string(), v, 12, "xy_v2");
  const std::string diagonal = RolloutValidation::reference_file(dir.string(), v, 12, "xy_v2", "diagonal");
  EXPECT_EQ(corner, RolloutValidation::reference_file(dir.string(), small_validation(), 12, "xy_v2"));
  EXPECT_NE(std::filesystem::path(corner).filename().string().find("validation_12_xy_v2_"), std::string::npos);
  EXPECT_NE(std::filesystem::path(diagonal).filename().string().find("validation_12_xy_v2_diagonal_"),
            std::string::npos);
  RolloutValidation validation(v, dir.string());
  EXPECT_EQ(validation.references_solved(), 2);
  ASSERT_EQ(validation.scenes().size(), 2u);
  EXPECT_EQ(validation.scenes()[0].handles, "corner");
  EXPECT_EQ(validation.scenes()[1].handles, "diagonal");
  EXPECT_TRUE(std::filesystem::exists(diagonal));
  // The score is the mean over both scenes: between the two scenes' own scores.
  const FNO2d model = load_fno(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt");
  const double both = validation.score(model).e3d;
  ValidationOptions only_diagonal = small_validation();
  only_diagonal.handles = {"diagonal"};
  const double corner_score = RolloutValidation(small_validation(), dir.string()).score(model).e3d;
  const double diagonal_score = RolloutValidation(only_diagonal, dir.string()).score(model).e3d;
  EXPECT_NE(corner_score, diagonal_score);
  EXPECT_NEAR(both, 0.5 * (corner_score + diagonal_score), 1e-12 * both);
}

TEST(RolloutValidation, SeveralGridsScoreTheGeometricMeanOfTheirMeans) {
  const testing::TempDir tmp;
  const auto& dir = tmp.path();
  ValidationOptions v = small_validation();
  v.resolutions = {10, 12};
  v.motions = {"xy_v2", "rot_h0"};
  EXPECT_EQ(RolloutValidation::grid_set_text(v), "10+12");
  EXPECT_EQ(RolloutValidation::grid_set_text(v, true), "10x10+12x12");
  EXPECT_EQ(RolloutValidation::grid_set_text(small_validation()), "12");
  RolloutValidation both(v, dir.string());
  EXPECT_EQ(both.references_solved(), 4);
  ASSERT_EQ(both.scenes().size(), 4u);
  EXPECT_EQ(both.scenes()[0].rows, 10);
  EXPECT_EQ(both.scenes()[1].motion, "rot_h0");
  EXPECT_EQ(both.scenes()[3].rows, 12);
  EXPECT_TRUE(std::filesystem::exists(RolloutValidation::reference_file(dir.string(), v, 10, "rot_h0")));
  // Each grid alone reuses the references the pair solved, and scores that grid's mean.
  const FNO2d model = load_fno(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt");
  const ValidationScore pair = both.score(model);
  ASSERT_FALSE(pair.diverged) << pair.divergence;
  ASSERT_EQ(pair.grid_e3d.size(), 2u);
  for (std::size_t g = 0; g < 2; ++g) {
    ValidationOptions one = v;
    one.resolutions = {v.resolutions[g]};
    RolloutValidation alone(one, dir.string());
    EXPECT_EQ(alone.references_solved(), 0);
    const ValidationScore score = alone.score(model);
    ASSERT_EQ(score.grid_e3d.size(), 1u);
    EXPECT_EQ(score.e3d, score.grid_e3d[0]);
    EXPECT_NEAR(pair.grid_e3d[g], score.e3d, 1e-12 * score.e3d) << v.resolutions[g];
  }
  EXPECT_NE(pair.grid_e3d[0], pair.grid_e3d[1]);
  EXPECT_NEAR(pair.e3d, std::sqrt(pair.grid_e3d[0] * pair.grid_e3d[1]), 1e-12 * pair.e3d);
}

TEST(RolloutValidation, ScoreIsDeterministicAndLeavesTheModelAlone) {
  const testing::TempDir tmp;
  const auto& dir = tmp.path();
  RolloutValidation validation(small_validation(), dir.string());
  FNO2d model = tiny_model();
  std::vector<torch::Tensor> before;
  for (const auto& p : model->parameters()) before.push_back(p.detach().clone());
  const bool training = model->is_training();
  const ValidationScore a = validation.score(model);
  const ValidationScore b = validation.score(model);
  ASSERT_FALSE(a.diverged) << a.divergence;
  EXPECT_TRUE(std::isfinite(a.e3d));
  EXPECT_GT(a.e3d, 0.0);
  EXPECT_EQ(a.e3d, b.e3d);
  EXPECT_EQ(model->is_training(), training);
  const auto after = model->parameters();
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_TRUE(torch::equal(before[i], after[i])) << "parameter " << i;
}

TEST(RolloutValidation, TheShippedModelScoresCloserThanAnUntrainedOne) {
  const testing::TempDir tmp;
  const auto& dir = tmp.path();
  RolloutValidation validation(small_validation(), dir.string());
  const ValidationScore shipped = validation.score(load_fno(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt"));
  FNO2d untrained(load_fno_options(std::string(FNOPT_SOURCE_DIR) + "/models/fnopt-32.pt"));
  const ValidationScore fresh = validation.score(untrained);
  ASSERT_FALSE(shipped.diverged) << shipped.divergence;
  EXPECT_LT(shipped.e3d, 0.5 * fresh.e3d) << "shipped " << shipped.e3d << ", untrained " << fresh.e3d;
}

// validate() throws an Error whose message starts with `message`.
void expect_refused(const ValidationOptions& v, const std::string& message) {
  try {
    v.validate();
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(message, 0), 0u) << e.what();
  }
}

TEST(RolloutValidation, RejectsBadOptionsNamingTheField) {
  ValidationOptions v = small_validation();
  v.motions = {"xy_v2", "sideways"};
  expect_refused(v, "validate.motions: unknown motion 'sideways'");
  v = small_validation();
  v.motions.clear();
  EXPECT_THROW(v.validate(), Error);
  v = small_validation();
  v.handles = {"corner", "sideways"};
  expect_refused(v, "validate.handles: unknown preset 'sideways'");
  v = small_validation();
  v.handles.clear();
  EXPECT_THROW(v.validate(), Error);
  // A motion a preset cannot carry (rot_h1 turns about the line through two handles).
  v = small_validation();
  v.motions = {"rot_h1"};
  v.handles = {"corner", "single-center"};
  expect_refused(v, "validate.handles: motion rot_h1 with handles single-center");
  v = small_validation();
  v.frames = 0;
  EXPECT_THROW(v.validate(), Error);
  v = small_validation();
  v.resolutions = {12, 2};
  expect_refused(v, "validate.resolutions: must be at least 3");
  v.resolutions.clear();
  expect_refused(v, "validate.resolutions: must name at least one grid");
  v = small_validation();
  v.subspace = 0;
  v.pqn_direction = true;
  EXPECT_THROW(v.validate(), Error);
}

TEST(RolloutValidation, NamesTheOptimizerItValidatesWith) {
  ValidationOptions v;
  EXPECT_EQ(v.optimizer(), "fnopt-ss");
  v.pqn_direction = true;
  EXPECT_EQ(v.optimizer(), "fnopt");
  v.subspace = 4;
  EXPECT_EQ(v.optimizer(), "fnopt-ss-k4-pqn");
  v.pqn_direction = false;
  EXPECT_EQ(v.optimizer(), "fnopt-ss-k4");
  v.subspace = 0;
  EXPECT_EQ(v.optimizer(), "fnopt-ls");
}

}  // namespace
}  // namespace fnopt
