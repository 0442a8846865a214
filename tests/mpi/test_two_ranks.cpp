// Two ranks (mpiexec -n 2): the communicator's collectives and messages, and data-parallel
// meta-training against one process with the whole batch. Every test runs on both ranks.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/training/meta_trainer.hpp>

namespace fnopt {
namespace {

const Communicator& world() { return Communicator::world(); }

// A folder both ranks see (one machine), named by rank 0.
std::filesystem::path shared_directory(const std::string& name) {
  std::string path;
  if (world().is_root()) {
    path = (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))).string();
    std::filesystem::create_directories(path);
  }
  world().broadcast(path);
  return path;
}

TEST(TwoRanks, RunUnderALauncher) {
  ASSERT_TRUE(MpiSession::active());
  ASSERT_EQ(world().size(), 2) << "run this test with mpiexec -n 2";
}

TEST(TwoRanks, CollectivesCombineBothRanks) {
  const int r = world().rank();
  double d[2] = {1.0 + r, 10.0 * r};
  world().sum(d, 2);
  EXPECT_EQ(d[0], 3.0);
  EXPECT_EQ(d[1], 10.0);
  float f[1] = {0.5f};
  world().sum(f, 1);
  EXPECT_EQ(f[0], 1.0f);
  EXPECT_EQ(world().sum(r + 1), 3);
  EXPECT_TRUE(world().any(r == 1));
  EXPECT_FALSE(world().any(false));
  std::string text = r == 0 ? "from rank 0, " + std::string(100000, 'x') : "rank 1's own";
  world().broadcast(text);
  EXPECT_EQ(text.substr(0, 12), "from rank 0,");
  EXPECT_EQ(text.size(), 12 + 100001u);
  const auto gathered = world().gather(std::string(r + 1, 'a' + r));
  if (r == 0)
    EXPECT_EQ(gathered, (std::vector<std::string>{"a", "bb"}));
  else
    EXPECT_TRUE(gathered.empty());
}

TEST(TwoRanks, RankOneMessagesReachRankZero) {
  if (world().rank() == 1) {
    world().send_to_root("first");
    world().send_to_root(std::string(200000, 'z'));  // beyond the eager limit: a rendezvous send
  } else {
    EXPECT_EQ(world().wait_for().text, "first");
    const Communicator::Message big = world().wait_for();
    EXPECT_EQ(big.source, 1);
    EXPECT_EQ(big.text.size(), 200000u);
    Communicator::Message none;
    EXPECT_FALSE(world().take_arrived(none));
  }
  world().barrier();
}

TrainOptions tiny_training() {
  TrainOptions o;
  o.pool.resolutions = {8};
  o.pool.environments = 16;
  o.model = FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4);
  o.batch = 8;
  o.steps = 100;
  return o;
}

// Largest |difference| between two models' parameters, relative to the largest |parameter|.
double relative_difference(FNO2d& a, FNO2d& b) {
  double difference = 0.0, size = 0.0;
  const auto pa = a->parameters(), pb = b->parameters();
  for (std::size_t i = 0; i < pa.size(); ++i) {
    difference = std::max(difference, (pa[i] - pb[i]).abs().max().item<double>());
    size = std::max(size, pa[i].abs().max().item<double>());
  }
  return difference / size;
}

// The tolerance of "the same weights": the two runs add the batch's gradients in another order
// (float32), so after 3 AdamW steps of lr 1e-3 the weights agree to float round-off; 1e-5 leaves
// room and is still far below what the 3 steps changed (checked below).
constexpr double kSameWeights = 1e-5;

TEST(DataParallelTraining, TwoRanksTakeTheStepsOfOneProcessWithTheWholeBatch) {
  MetaTrainer distributed(tiny_training(), {}, world());
  MetaTrainer alone(tiny_training(), {}, Communicator::self());
  for (int i = 0; i < 3; ++i) {
    const TrainStepStats d = distributed.step(), a = alone.step();
    EXPECT_NEAR(d.loss, a.loss, 1e-5 * std::abs(a.loss)) << "step " << i;
    EXPECT_NEAR(d.gradient_norm, a.gradient_norm, 1e-4 * a.gradient_norm) << "step " << i;
    EXPECT_EQ(d.renewed, a.renewed);
  }
  const double difference = relative_difference(distributed.model(), alone.model());
  EXPECT_LT(difference, kSameWeights);
  // And the steps did move the weights: the test could fail.
  MetaTrainer start(tiny_training(), {}, Communicator::self());
  EXPECT_GT(relative_difference(start.model(), alone.model()), 100 * kSameWeights);
  EXPECT_LT(relative_difference(distributed.output_model(), alone.output_model()), kSameWeights);
}

TEST(DataParallelTraining, CheckpointOfTwoRanksResumesInOneProcess) {
  const auto dir = shared_directory("fnopt_test_mpi_checkpoint");
  const std::string checkpoint = (dir / "checkpoint.pt").string();
  MetaTrainer distributed(tiny_training(), {}, world());
  for (int i = 0; i < 2; ++i) distributed.step();
  distributed.save_checkpoint(checkpoint);  // rank 0 writes every environment, gathered
  world().barrier();
  // One process resumes it; the two ranks go on from where they are: the same steps.
  MetaTrainer resumed(tiny_training(), checkpoint, Communicator::self());
  EXPECT_EQ(resumed.completed_steps(), 2);
  for (int i = 0; i < 2; ++i) {
    const TrainStepStats d = distributed.step(), r = resumed.step();
    EXPECT_NEAR(d.loss, r.loss, 1e-5 * std::abs(r.loss)) << "step " << i;
  }
  EXPECT_LT(relative_difference(distributed.model(), resumed.model()), kSameWeights);
  // And two ranks resume it too.
  MetaTrainer resumed_two(tiny_training(), checkpoint, world());
  EXPECT_EQ(resumed_two.completed_steps(), 2);
  world().barrier();
  if (world().is_root()) std::filesystem::remove_all(dir);
}

TEST(DataParallelTraining, BatchMustSplitEvenly) {
  TrainOptions options = tiny_training();
  options.batch = 3;
  EXPECT_THROW(MetaTrainer(options, {}, world()), Error);
}

}  // namespace
}  // namespace fnopt
