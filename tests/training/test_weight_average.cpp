// The weight average: it is the exponential moving average of what it is fed, it owns its
// weights, and in meta-training it observes the run without changing it, ramps its decay up,
// survives a checkpoint, and starts at the trained weights of a checkpoint saved without one.
#include <gtest/gtest.h>

#include <fnopt/training/meta_trainer.hpp>
#include <fnopt/training/weight_average.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

FNO2dOptions tiny_options() {
  return FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4);
}

FNO2d seeded_model(int seed) {
  torch::manual_seed(seed);
  return FNO2d(tiny_options());
}

TrainOptions tiny_training(double average_decay) {
  TrainOptions o;
  o.pool.resolutions = {8};
  o.pool.environments = 4;
  o.model = tiny_options();
  o.batch = 2;
  o.average_decay = average_decay;
  return o;
}

// Largest absolute difference between the parameters of two models of the same shape.
double max_difference(const FNO2d& a, const FNO2d& b) {
  const auto pa = a->parameters(), pb = b->parameters();
  double worst = 0.0;
  for (std::size_t i = 0; i < pa.size(); ++i) worst = std::max(worst, (pa[i] - pb[i]).abs().max().item<double>());
  return worst;
}

TEST(WeightAverage, IsTheExponentialMovingAverageOfItsUpdates) {
  const FNO2d a = seeded_model(1), b = seeded_model(2);
  WeightAverage average(a);
  EXPECT_EQ(max_difference(average.model(), a), 0.0);
  average.update(b, 0.9);
  average.update(b, 0.9);
  // After two updates with b: 0.81 a + 0.19 b, parameter by parameter.
  const auto pa = a->parameters(), pb = b->parameters(), pw = average.model()->parameters();
  ASSERT_EQ(pw.size(), pa.size());
  for (std::size_t i = 0; i < pw.size(); ++i)
    EXPECT_TRUE(torch::allclose(pw[i], 0.81 * pa[i] + 0.19 * pb[i], 1e-5, 1e-6)) << "parameter " << i;
}

TEST(WeightAverage, OwnsItsWeights) {
  FNO2d a = seeded_model(1);
  const FNO2d copy = seeded_model(1);
  WeightAverage average(a);
  torch::NoGradGuard no_grad;
  for (auto& p : a->parameters()) p.add_(1.0);
  EXPECT_EQ(max_difference(average.model(), copy), 0.0);
  average.reset_to(a);
  EXPECT_EQ(max_difference(average.model(), a), 0.0);
}

TEST(WeightAverage, RejectsADecayOutsideZeroToOne) {
  const FNO2d a = seeded_model(1);
  WeightAverage average(a);
  EXPECT_THROW(average.update(a, 1.0), Error);
  EXPECT_THROW(average.update(a, -0.1), Error);
  EXPECT_THROW(tiny_training(1.0).validate(), Error);
}

TEST(WeightAverage, LeavesTheTrainingStepsUnchanged) {
  MetaTrainer plain(tiny_training(0.0)), averaged(tiny_training(0.9));
  for (int i = 0; i < 4; ++i) EXPECT_EQ(plain.step().loss, averaged.step().loss) << "step " << i;
  EXPECT_EQ(max_difference(plain.model(), averaged.model()), 0.0);
  EXPECT_EQ(plain.output_model().ptr(), plain.model().ptr());
  EXPECT_GT(max_difference(averaged.output_model(), averaged.model()), 0.0);
}

TEST(WeightAverage, RampsItsDecayUpOverTheFirstSteps) {
  // After t steps the decay is min(d, (1 + t)/(10 + t)): 0.1 for the first step, so a run
  // from scratch does not keep its random start in the average.
  MetaTrainer trainer(tiny_training(0.9));
  std::vector<torch::Tensor> start;
  for (const auto& p : trainer.model()->parameters()) start.push_back(p.detach().clone());
  trainer.step();
  const auto trained = trainer.model()->parameters(), average = trainer.output_model()->parameters();
  for (std::size_t i = 0; i < start.size(); ++i)
    EXPECT_TRUE(torch::allclose(average[i], 0.1 * start[i] + 0.9 * trained[i], 1e-5, 1e-6)) << "parameter " << i;
}

TEST(WeightAverage, SurvivesACheckpoint) {
  const testing::TempDir tmp;
  const std::string checkpoint = (tmp.path() / "checkpoint.pt").string();
  MetaTrainer original(tiny_training(0.9));
  for (int i = 0; i < 3; ++i) original.step();
  original.save_checkpoint(checkpoint);
  for (int i = 0; i < 2; ++i) original.step();

  MetaTrainer resumed(tiny_training(0.9), checkpoint);
  for (int i = 0; i < 2; ++i) resumed.step();
  EXPECT_LT(max_difference(resumed.output_model(), original.output_model()), 1e-6);
  EXPECT_GT(max_difference(resumed.output_model(), resumed.model()), 0.0);
}

TEST(WeightAverage, StartsAtTheTrainedWeightsOfACheckpointSavedWithoutOne) {
  const testing::TempDir tmp;
  const std::string checkpoint = (tmp.path() / "checkpoint.pt").string();
  MetaTrainer plain(tiny_training(0.0));
  for (int i = 0; i < 3; ++i) plain.step();
  plain.save_checkpoint(checkpoint);

  MetaTrainer averaged(tiny_training(0.9), checkpoint);
  EXPECT_EQ(averaged.completed_steps(), 3);
  EXPECT_EQ(max_difference(averaged.output_model(), plain.model()), 0.0);
  averaged.step();
  EXPECT_GT(max_difference(averaged.output_model(), averaged.model()), 0.0);
}

}  // namespace
}  // namespace fnopt
