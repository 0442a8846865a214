// Meta-training: the energy loss's gradient is the analytic one, a tiny model learns on a fixed
// batch, and a resumed checkpoint takes exactly the steps the original run took.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_pqn.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/energy_loss.hpp>
#include <fnopt/training/meta_trainer.hpp>
#include <fnopt/training/probe_loss.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

PoolOptions small_pool() {
  PoolOptions pool;
  pool.resolutions = {8};
  pool.environments = 4;
  return pool;
}

TrainOptions tiny_training() {
  TrainOptions o;
  o.pool = small_pool();
  o.model = FNO2dOptions().width(4).fourier_layers(2).modes_x(4).modes_y(4).lifting_channels(8).projection_channels(4);
  o.batch = 2;
  o.steps = 100;
  return o;
}

// Adam steps that lower `loss` on a fixed batch: its value before and after.
template <class Loss>
std::pair<double, double> train_on_fixed_batch(torch::optim::Adam& adam, Loss&& loss, int steps) {
  const double initial = loss().template item<double>();
  for (int i = 0; i < steps; ++i) {
    adam.zero_grad();
    loss().backward();
    adam.step();
  }
  return {initial, loss().template item<double>()};
}

// Saves `original`'s checkpoint, takes `steps` more steps, and checks that a trainer resumed from
// the checkpoint takes the same ones (losses to float round-off).
void expect_resumes_exactly(MetaTrainer& original, const TrainOptions& options, const std::string& name, int steps) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::create_directories(dir);
  const std::string checkpoint = (dir / "checkpoint.pt").string();
  original.save_checkpoint(checkpoint);
  std::vector<double> expected;
  for (int i = 0; i < steps; ++i) expected.push_back(original.step().loss);
  MetaTrainer resumed(options, checkpoint);
  EXPECT_EQ(resumed.completed_steps(), original.completed_steps() - steps);
  for (int i = 0; i < steps; ++i)
    EXPECT_NEAR(resumed.step().loss, expected[i], 1e-6 * std::abs(expected[i])) << name << ", step " << i;
  std::filesystem::remove_all(dir);
}

TEST(EnergyLoss, GradientMatchesFiniteDifferences) {
  TrainingEnv a(small_pool(), 7, 0), b(small_pool(), 7, 1);
  EnergyLossBatch batch;
  batch.envs = {&a, &b};
  for (TrainingEnv* env : batch.envs) batch.current_loss.push_back(env->objective().value(env->acceleration()));
  torch::manual_seed(1);
  auto delta = (0.01 * torch::randn({6, 1, 8, 8}, torch::kFloat32)) *
               torch::cat({free_mask(a.dirichlet(), a.grid()).expand({3, 1, 8, 8}),
                           free_mask(b.dirichlet(), b.grid()).expand({3, 1, 8, 8})});
  delta.requires_grad_(true);
  EnergyLoss::apply(delta, &batch).backward();
  const auto analytic = delta.grad().clone();
  ASSERT_GT(analytic.abs().max().item<double>(), 0.0);
  // Central differences in double precision through the same forward pass, at entries of
  // both environments.
  const float eps = 1e-3f;
  for (int index : {5, 70, 130, 200, 300}) {
    auto plus = delta.detach().clone(), minus = delta.detach().clone();
    plus.view({-1})[index] += eps;
    minus.view({-1})[index] -= eps;
    const double fd =
        (EnergyLoss::apply(plus, &batch).item<double>() - EnergyLoss::apply(minus, &batch).item<double>()) / (2 * eps);
    EXPECT_NEAR(analytic.view({-1})[index].item<double>(), fd, 1e-2 * std::abs(fd) + 1e-6) << "entry " << index;
  }
}

TEST(EnergyLoss, ScoredAfterTheSubspaceStepItsGradientMatchesFiniteDifferences) {
  PoolOptions pool = small_pool();
  pool.subspace = 8;
  TrainingEnv env(pool, 7, 0);
  // Two proposals of -g in cell widths taken by the rule first, so that a direction is kept.
  StepProblem problem(env.objective(), env.dirichlet());
  VecX gradient;
  double value = problem.value_gradient(env.acceleration(), gradient);
  for (int i = 0; i < 2; ++i) {
    const torch::Tensor g = to_coordinate_samples(gradient, env.grid());
    const LearnedStep proposal{to_coordinate_samples(gradient, env.grid(), -0.02 / gradient.norm()),
                               torch::full({3, 1, 1, 1}, 0.5)};
    env.rule().apply(problem, g, proposal, env.acceleration(), value, gradient);
  }
  ASSERT_GE(env.rule().pairs().size(), 1);

  EnergyLossBatch batch;
  batch.envs = {&env};
  batch.after_subspace_step = true;
  batch.current_loss = {value};
  batch.current_gradient = {gradient};
  torch::manual_seed(2);
  const auto mask = free_mask(env.dirichlet(), env.grid()).expand({3, 1, 8, 8});
  auto delta = (-to_coordinate_samples(gradient, env.grid(), 0.02 / gradient.norm()) +
                0.005 * torch::randn({3, 1, 8, 8}, torch::kFloat32)) *
               mask;
  delta.requires_grad_(true);
  const double loss = EnergyLoss::apply(delta, &batch).item<double>();
  EnergyLossBatch as_proposal = batch;
  as_proposal.after_subspace_step = false;
  // The rule ends lower than the proposal: the subspace step was taken.
  ASSERT_LT(loss, EnergyLoss::apply(delta.detach(), &as_proposal).item<double>());
  EnergyLoss::apply(delta, &batch).backward();
  const auto analytic = delta.grad().clone();
  const float eps = 1e-3f;
  for (int index : {9, 20, 83, 150}) {
    auto plus = delta.detach().clone(), minus = delta.detach().clone();
    plus.view({-1})[index] += eps;
    minus.view({-1})[index] -= eps;
    const double fd =
        (EnergyLoss::apply(plus, &batch).item<double>() - EnergyLoss::apply(minus, &batch).item<double>()) / (2 * eps);
    EXPECT_NEAR(analytic.view({-1})[index].item<double>(), fd, 1e-2 * std::abs(fd) + 1e-6) << "entry " << index;
  }
}

TEST(MetaTraining, TinyModelLowersTheLossOnAFixedBatch) {
  TrainingEnv a(small_pool(), 11, 0), b(small_pool(), 11, 1);
  torch::manual_seed(5);
  FNO2d model(tiny_training().model);
  torch::optim::Adam adam(model->parameters(), torch::optim::AdamOptions(3e-3));
  EnergyLossBatch batch;
  batch.envs = {&a, &b};
  VecX g;
  std::vector<torch::Tensor> gradients, masks;
  for (TrainingEnv* env : batch.envs) {
    batch.current_loss.push_back(env->objective().value_gradient(env->acceleration(), g));
    env->dirichlet().zero_fixed(g);
    gradients.push_back(to_coordinate_samples(g, env->grid()));
    masks.push_back(free_mask(env->dirichlet(), env->grid()).expand({3, 1, 8, 8}));
  }
  const auto gradient = torch::cat(gradients), mask = torch::cat(masks);
  auto loss_now = [&] {
    const LearnedStep step = learned_step(model, gradient, LearnedState{}, mask);
    return EnergyLoss::apply(step.delta, &batch);
  };
  const auto [initial, trained] = train_on_fixed_batch(adam, loss_now, 30);
  std::printf("fixed-batch loss: %.5f -> %.5f\n", initial, trained);
  EXPECT_LT(trained, initial - 0.05);
}

TEST(MetaTraining, ResumedCheckpointTakesTheSameNextSteps) {
  MetaTrainer original(tiny_training());
  for (int i = 0; i < 4; ++i) original.step();
  expect_resumes_exactly(original, tiny_training(), "fnopt_test_resume", 6);
}

TEST(MetaTraining, SubspaceRuleChangesThePoolAndResumesWithItsKeptProposals) {
  TrainOptions options = tiny_training();
  options.pool.subspace = 8;
  MetaTrainer original(options), as_is(tiny_training());
  std::vector<double> losses, losses_as_is;
  for (int i = 0; i < 4; ++i) {
    losses.push_back(original.step().loss);
    losses_as_is.push_back(as_is.step().loss);
  }
  // The first step sees the same pool; the pool the rule leaves behind differs.
  EXPECT_EQ(losses[0], losses_as_is[0]);
  EXPECT_NE(losses, losses_as_is);
  expect_resumes_exactly(original, options, "fnopt_test_resume_subspace", 8);
}

// fnopt's rule in the pool: pqn's pair joins the kept ones before each proposal, so a loss
// scored past the subspace step differs from fnopt-ss's from the first step on; a checkpoint
// resumes it exactly; it needs the subspace step.
TEST(MetaTraining, PqnDirectionJoinsTheSubspaceBeforeEachProposalAndResumes) {
  TrainOptions options = tiny_training(), without = tiny_training();
  options.pool.subspace = without.pool.subspace = 8;
  options.score_after_subspace_step = without.score_after_subspace_step = true;
  options.pool.pqn_direction = true;
  MetaTrainer original(options), fnopt_ss(without);
  const double first = original.step().loss, first_without = fnopt_ss.step().loss;
  EXPECT_TRUE(std::isfinite(first));
  EXPECT_NE(first, first_without);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(original.step().loss));
  expect_resumes_exactly(original, options, "fnopt_test_resume_pqn_direction", 4);
  options.pool.subspace = 0;
  options.score_after_subspace_step = false;
  EXPECT_THROW(options.validate(), Error);
}

TEST(MetaTraining, ScoringAfterTheSubspaceStepNeedsThePoolToTakeIt) {
  TrainOptions options = tiny_training();
  options.score_after_subspace_step = true;
  EXPECT_THROW(options.validate(), Error);
  options.pool.subspace = 8;
  EXPECT_NO_THROW(options.validate());
}

// A pool of two grids: environment e lives on the (e mod 2)-th, and a batch holding one of each
// scores the mean of the two environments' own losses, each through the model at its own size.
TEST(MetaTraining, APoolOfTwoGridsScoresEachEnvironmentAtItsOwnSize) {
  auto first_loss = [](std::vector<int> resolutions, int environments) {
    TrainOptions o = tiny_training();
    o.pool.resolutions = std::move(resolutions);
    o.pool.environments = o.batch = environments;  // one environment per stratum: the batch is the pool
    o.newton_weight = 0.0;
    return MetaTrainer(o).step().loss;
  };
  const double mixed = first_loss({8, 12}, 2);
  const double env0_at_8 = first_loss({8}, 1);
  // Environment 1 of a 12^2 pool of two, from that pool's mean and its environment 0 alone.
  const double env1_at_12 = 2.0 * first_loss({12}, 2) - first_loss({12}, 1);
  EXPECT_NEAR(mixed, 0.5 * (env0_at_8 + env1_at_12), 1e-5 * std::abs(mixed));

  TrainingEnv at8(tiny_training().pool, 1, 0), at12(
                                                   [] {
                                                     PoolOptions pool = tiny_training().pool;
                                                     pool.resolutions = {8, 12};
                                                     return pool;
                                                   }(),
                                                   1, 1);
  EXPECT_EQ(at8.grid().rows, 8);
  EXPECT_EQ(at12.grid().rows, 12);
}

TEST(MetaTraining, APoolOfTwoGridsResumesAndNeedsTheEnergyObjective) {
  TrainOptions options = tiny_training();
  options.pool.resolutions = {8, 12};
  MetaTrainer original(options);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(original.step().loss));
  expect_resumes_exactly(original, options, "fnopt_test_resume_two_grids", 4);

  TrainOptions probe = options;
  probe.objective = TrainObjective::Probe;
  EXPECT_THROW(probe.validate(), Error);
  options.pool.resolutions = {8, 2};
  EXPECT_THROW(options.validate(), Error);
}

// A pool measured against pqn's K iterations instead of Newton's step: its losses differ from
// the first step on (the same environments, another L*), it resumes exactly, and its checkpoint
// is not one of the Newton-referenced run (the options' signature names the reference).
TEST(MetaTraining, APqnReferencedPoolTrainsResumesAndIsItsOwnRun) {
  TrainOptions options = tiny_training();
  options.pool.reference_pqn_iterations = 20;
  MetaTrainer original(options), newton(tiny_training());
  const double first = original.step().loss, first_newton = newton.step().loss;
  EXPECT_TRUE(std::isfinite(first));
  EXPECT_NE(first, first_newton);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(original.step().loss));
  expect_resumes_exactly(original, options, "fnopt_test_resume_pqn_reference", 4);
  EXPECT_NE(options.signature().find(" reference=pqn20"), std::string::npos) << options.signature();
  EXPECT_EQ(tiny_training().signature().find("reference="), std::string::npos);
}

TEST(MetaTraining, RejectsACheckpointOfOtherOptions) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_resume_other";
  std::filesystem::create_directories(dir);
  const std::string checkpoint = (dir / "checkpoint.pt").string();
  MetaTrainer(tiny_training()).save_checkpoint(checkpoint);
  TrainOptions other = tiny_training();
  other.batch = 3;
  EXPECT_THROW(static_cast<void>(MetaTrainer(other, checkpoint)), Error);
  std::filesystem::remove_all(dir);
}

TEST(MetaTraining, ProbeObjectiveLowersRemainingOnAFixedBatch) {
  for (const int iterations : {1, 4}) {
    TrainingEnv a(small_pool(), 11, 0), b(small_pool(), 11, 1);
    torch::manual_seed(5);
    FNO2d model(tiny_training().model);
    torch::optim::Adam adam(model->parameters(), torch::optim::AdamOptions(2e-2));
    std::vector<std::unique_ptr<ProbeLoss>> probes;
    std::vector<torch::Tensor> gradients, masks;
    for (TrainingEnv* env : {&a, &b}) {
      StepProblem problem(env->objective(), env->dirichlet());
      VecX g;
      problem.value_gradient(env->acceleration(), g);
      ProbeLossOptions options;
      options.iterations = iterations;
      probes.push_back(std::make_unique<ProbeLoss>(problem, env->acceleration(), g, options));
      gradients.push_back(to_coordinate_samples(g, env->grid()));
      masks.push_back(free_mask(env->dirichlet(), env->grid()).expand({3, 1, 8, 8}));
    }
    const auto gradient = torch::cat(gradients), mask = torch::cat(masks);
    auto remaining_now = [&] {
      const LearnedStep step = learned_step(model, gradient, LearnedState{}, mask);
      torch::Tensor sum = torch::zeros({}, torch::kFloat64);
      for (int i = 0; i < 2; ++i)
        sum = sum + probes[i]->remaining(
                        probes[i]->free_dofs(gate_coordinates(step.delta.narrow(0, 3 * i, 3), gradients[i])));
      return sum / 2;
    };
    const auto [initial, trained] = train_on_fixed_batch(adam, remaining_now, 60);
    std::printf("fixed-batch probe remainder after %d pqn iterations: %.5f -> %.5f (pqn alone %.5f, %.5f)\n",
                iterations, initial, trained, probes[0]->remaining_without_probe(),
                probes[1]->remaining_without_probe());
    EXPECT_LT(trained, 0.8 * initial) << iterations << " iterations";
  }
}

TEST(MetaTraining, ProbeObjectiveFollowsNewtonAndResumes) {
  TrainOptions options = tiny_training();
  options.objective = TrainObjective::Probe;
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_resume_probe";
  std::filesystem::create_directories(dir);
  const std::string checkpoint = (dir / "checkpoint.pt").string();
  MetaTrainer original(options);
  for (int i = 0; i < 3; ++i) {
    const TrainStepStats s = original.step();
    EXPECT_TRUE(std::isfinite(s.loss));
    EXPECT_GE(s.mean_ratio, -1e-9);
    EXPECT_GE(s.ratio_without_probe, -1e-9);
  }
  original.save_checkpoint(checkpoint);
  std::vector<double> expected;
  for (int i = 0; i < 4; ++i) expected.push_back(original.step().loss);
  MetaTrainer resumed(options, checkpoint);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(resumed.step().loss, expected[i], 1e-6 * std::abs(expected[i])) << "step " << i;
  // A checkpoint of the energy objective, or one scored after another number of pqn iterations,
  // is another run.
  EXPECT_THROW(static_cast<void>(MetaTrainer(tiny_training(), checkpoint)), Error);
  TrainOptions longer = options;
  longer.probe.iterations = 3;
  EXPECT_THROW(static_cast<void>(MetaTrainer(longer, checkpoint)), Error);
  TrainOptions energy = tiny_training();
  energy.probe.iterations = 3;
  EXPECT_THROW(energy.validate(), Error);
  options.pool.subspace = 8;
  EXPECT_THROW(options.validate(), Error);
  std::filesystem::remove_all(dir);
}

// A tiny model with fixed random weights, saved to `path`.
FNO2d saved_initial_model(const std::string& path) {
  torch::manual_seed(9);
  FNO2d model(tiny_training().model);
  save_fno(path, model);
  return model;
}

TEST(MetaTraining, AFreshRunStartsFromTheInitialModel) {
  const auto dir = std::filesystem::temp_directory_path() / "fnopt_test_initial_model";
  std::filesystem::create_directories(dir);
  TrainOptions options = tiny_training();
  options.initial_model = (dir / "initial.pt").string();
  const FNO2d initial = saved_initial_model(options.initial_model);
  MetaTrainer trainer(options);
  const auto given = initial->named_parameters();
  for (const auto& p : trainer.model()->named_parameters())
    EXPECT_TRUE(torch::equal(p.value(), given[p.key()])) << p.key();
  options.model.width(6);
  EXPECT_THROW(static_cast<void>(MetaTrainer(options)), Error);
  // A model of a removed input layout (fnopt train --pqn-input's) is refused, naming the option.
  options = tiny_training();
  options.initial_model = (dir / "initial.pt").string();
  save_fno(options.initial_model, FNO2d(FNO2dOptions(options.model).in_channels(4)));
  try {
    MetaTrainer refused(options);
    ADD_FAILURE() << "a model of the removed --pqn-input layout was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              options.initial_model + ": a model of fnopt train --pqn-input, an option this version no longer has");
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fnopt
