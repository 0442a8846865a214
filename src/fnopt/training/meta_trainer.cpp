#include <fnopt/training/meta_trainer.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/learned/grid_tensor.hpp>
#include <fnopt/learned/learned_pqn.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/training/energy_loss.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

// A checkpoint's name for the k-th state tensor of environment e.
std::string environment_key(int e, int k) { return "env" + std::to_string(e) + "_" + std::to_string(k); }

}  // namespace

void TrainOptions::validate() const {
  pool.validate();
  fnopt::validate(model);
  check_learned_model(model, "train.model");
  require(steps > 0, "train.steps", "must be positive");
  require(batch > 0 && batch <= pool.environments, "train.batch", "must lie in [1, environments]");
  require(learning_rate > 0.0, "train.learning_rate", "must be positive");
  require(weight_decay >= 0.0, "train.weight_decay", "must not be negative");
  require(decay_every > 0, "train.decay_every", "must be positive");
  require(clip_norm > 0.0, "train.clip_norm", "must be positive");
  require(newton_weight >= 0.0, "train.newton_weight", "must not be negative");
  require(average_decay >= 0.0 && average_decay < 1.0, "train.average_decay", "must lie in [0, 1)");
  require(objective == TrainObjective::Energy || (pool.subspace == 0 && !score_after_subspace_step), "train.objective",
          "the probe objective takes no subspace step (the pool follows Newton's solution)");
  probe.validate();
  require(objective == TrainObjective::Probe || probe.iterations == 1, "train.probe_iterations",
          "applies to the probe objective only");
  require(objective == TrainObjective::Probe || probe.surface == ProbeSurface::QuadraticModel, "train.probe_surface",
          "applies to the probe objective only");
  // Grids of several sizes go through the model in one pass per size (MetaTrainer::step); the
  // probe step takes the batch in one piece.
  require(pool.resolutions.size() == 1 || objective == TrainObjective::Energy, "train.resolutions",
          "several resolutions need the energy objective");
  require(!score_after_subspace_step || pool.subspace > 0, "train.score_after_subspace_step",
          "needs a pool that takes the subspace step (subspace > 0: fnopt train --subspace K)");
}

std::string TrainOptions::signature() const {
  std::ostringstream s;
  s << "res=";
  for (std::size_t i = 0; i < pool.resolutions.size(); ++i) s << (i ? "," : "") << pool.resolutions[i];
  s << " envs=" << pool.environments << " width=" << model.width() << " layers=" << model.fourier_layers()
    << " modes=" << model.modes_x() << "x" << model.modes_y() << " lifting=" << model.lifting_channels()
    << " projection=" << model.projection_channels() << " batch=" << batch << " lr=" << learning_rate
    << " newton_weight=" << newton_weight << " seed=" << seed;
  if (objective == TrainObjective::Probe) s << " objective=probe";
  if (probe.iterations != 1) s << " probe_iterations=" << probe.iterations;
  if (probe.surface == ProbeSurface::Energy) s << " probe_surface=energy";
  if (pool.reference_pqn_iterations > 0) s << " reference=pqn" << pool.reference_pqn_iterations;
  return s.str();
}

MetaTrainer::MetaTrainer(const TrainOptions& options, const std::string& checkpoint, const Communicator& processes)
    : options_(options), processes_(processes), model_(nullptr), rng_(options.seed) {
  options_.validate();
  require(options_.batch % processes_.size() == 0, "train.batch",
          "must be a multiple of the processes (" + std::to_string(processes_.size()) + ")");
  torch::manual_seed(options_.seed);
  model_ = FNO2d(options_.model);
  if (!options_.initial_model.empty() && checkpoint.empty()) {
    const FNO2d initial = load_learned_model(options_.initial_model);
    const FNO2dOptions& given = initial->options;
    require(given.in_channels() == options_.model.in_channels() && given.width() == options_.model.width() &&
                given.fourier_layers() == options_.model.fourier_layers() &&
                given.modes_x() == options_.model.modes_x() && given.modes_y() == options_.model.modes_y() &&
                given.lifting_channels() == options_.model.lifting_channels() &&
                given.projection_channels() == options_.model.projection_channels(),
            options_.initial_model, "not the shape of the model to train (width, layers, modes, lifting, projection)");
    torch::NoGradGuard no_grad;
    const auto from = initial->named_parameters();
    for (auto& p : model_->named_parameters()) p.value().copy_(from[p.key()]);
  }
  adam_ = std::make_unique<torch::optim::AdamW>(
      model_->parameters(), torch::optim::AdamWOptions(options_.learning_rate).weight_decay(options_.weight_decay));
  if (options_.average_decay > 0.0) average_.emplace(model_);
  if (!checkpoint.empty()) {
    restore(checkpoint);
    return;
  }
  for (int id = 0; id < options_.pool.environments; ++id)
    pool_.push_back(owns(id) ? std::make_unique<TrainingEnv>(options_.pool, options_.seed, id) : nullptr);
}

void MetaTrainer::sum_gradients_over_processes() {
  if (processes_.size() == 1) return;
  std::vector<torch::Tensor> gradients;
  for (const auto& p : model_->parameters()) gradients.push_back(p.grad().reshape(-1));
  torch::Tensor flat = torch::cat(gradients).to(torch::kFloat32).contiguous();
  processes_.sum(flat.data_ptr<float>(), static_cast<std::size_t>(flat.numel()));
  int64_t offset = 0;
  for (const auto& p : model_->parameters()) {
    const int64_t n = p.grad().numel();
    p.grad().copy_(flat.narrow(0, offset, n).view_as(p.grad()));
    offset += n;
  }
}

TrainStepStats MetaTrainer::step() {
  TrainStepStats stats;
  stats.learning_rate = options_.learning_rate * std::pow(0.5, step_ / options_.decay_every);
  for (auto& group : adam_->param_groups())
    static_cast<torch::optim::AdamWOptions&>(group.options()).lr(stats.learning_rate);

  // A batch of distinct environments, one per stratum: position i from the environments
  // e = i, i + batch, i + 2 batch, ...; this process takes the positions it owns.
  const int environments = static_cast<int>(pool_.size()), batch_size = options_.batch;
  std::vector<int> order;
  for (int i = 0; i < batch_size; ++i) {
    const int stratum = (environments - i + batch_size - 1) / batch_size;
    const int e = i + batch_size * std::uniform_int_distribution<int>(0, stratum - 1)(rng_);
    if (owns(e)) order.push_back(e);
  }
  if (options_.objective == TrainObjective::Probe) {
    probe_step(order, stats);
    ++step_;
    return stats;
  }

  // The batch's environments grouped by grid size (one group unless the pool mixes resolutions):
  // the model runs once per group, and the groups' losses, each its share of the batch mean, add up.
  std::vector<std::vector<int>> groups;
  for (const int e : order) {
    auto same = std::find_if(groups.begin(), groups.end(), [&](const std::vector<int>& group) {
      return pool_[group.front()]->grid().vertex_count() == pool_[e]->grid().vertex_count();
    });
    if (same == groups.end())
      groups.push_back({e});
    else
      same->push_back(e);
  }
  std::vector<GroupStep> steps(groups.size());
  torch::Tensor loss;
  double newton_loss = 0.0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const torch::Tensor group_loss = group_forward(groups[g], steps[g], newton_loss);
    loss = g == 0 ? group_loss : loss + group_loss;
  }
  if (options_.newton_weight > 0.0) stats.newton_loss = processes_.sum(newton_loss);

  take_gradient_step(loss, stats);

  // Each environment takes its update by its proposal rule, as inference would.
  double ratio_sum = 0.0;
  int finite = 0;
  for (GroupStep& group : steps)
    for (std::size_t i = 0; i < group.batch.envs.size(); ++i) {
      TrainingEnv& env = *group.batch.envs[i];
      const int j = static_cast<int>(i);
      const LearnedStep proposal{group.update.delta.narrow(0, 3 * j, 3).detach(),
                                 group.update.scale.narrow(0, 3 * j, 3).detach()};
      if (!std::isfinite(group.batch.ratio[i]) || !torch::isfinite(proposal.delta).all().item<bool>()) {
        env.renew();
        ++stats.renewed;
        continue;
      }
      ratio_sum += group.batch.ratio[i];
      ++finite;
      StepProblem problem(env.objective(), env.dirichlet());
      double value = group.batch.current_loss[i];
      const LearnedState next = env.rule().apply(problem, group.gradients[i], proposal, env.acceleration(), value,
                                                 group.batch.current_gradient[i]);
      env.previous_gradient = next.gradient;
      env.previous_delta = next.delta;
      env.scale = next.scale;
      env.finish_iteration();
    }
  double counts[3] = {ratio_sum, static_cast<double>(finite), static_cast<double>(stats.renewed)};
  processes_.sum(counts, 3);
  stats.mean_ratio = counts[1] > 0 ? counts[0] / counts[1] : NAN;
  stats.renewed = static_cast<int>(counts[2]);
  ++step_;
  return stats;
}

torch::Tensor MetaTrainer::group_forward(const std::vector<int>& members, GroupStep& group, double& newton_loss) {
  // Environments keep their state per coordinate ([3, 1, R, C], scale [3, 1, 1, 1]), as the
  // model sees it.
  const int count = static_cast<int>(members.size());
  EnergyLossBatch& batch = group.batch;
  batch.after_subspace_step = options_.score_after_subspace_step;
  batch.environments_in_all = options_.batch;
  batch.current_gradient.resize(count);
  std::vector<torch::Tensor> previous_gradients, previous_deltas, scales, masks, newton_deltas;
  for (int i = 0; i < count; ++i) {
    TrainingEnv& env = *pool_[members[i]];
    VecX& g = batch.current_gradient[i];
    batch.envs.push_back(&env);
    StepProblem problem(env.objective(), env.dirichlet());
    batch.current_loss.push_back(problem.value_gradient(env.acceleration(), g));
    // fnopt's pair joins the kept ones before the proposal, so the loss past the subspace
    // step scores the proposal with it.
    env.rule().add_pqn_direction(problem, env.acceleration(), g);
    group.gradients.push_back(to_coordinate_samples(g, env.grid()));
    previous_gradients.push_back(env.previous_gradient);
    previous_deltas.push_back(env.previous_delta);
    scales.push_back(env.scale);
    masks.push_back(free_mask(env.dirichlet(), env.grid()).expand({3, 1, env.grid().rows, env.grid().cols}));
    const double to_grid_units = 1.0 / acceleration_per_grid_unit(env.grid(), env.dt());
    newton_deltas.push_back(
        to_coordinate_samples(env.reference_acceleration() - env.acceleration(), env.grid(), to_grid_units));
  }
  const torch::Tensor gradient = torch::cat(group.gradients);
  const LearnedState state{torch::cat(previous_gradients), torch::cat(previous_deltas), torch::cat(scales)};
  group.update = learned_step(model_, gradient, state, torch::cat(masks));
  torch::Tensor loss = EnergyLoss::apply(group.update.delta, &batch);
  if (options_.newton_weight > 0.0) {
    const auto target = torch::cat(newton_deltas).view({count, -1});
    const auto error = (group.update.delta.view({count, -1}) - target).pow(2).sum(1);
    // Corrections below 1e-4 cell widths (an environment at rest) are not worth a target.
    const double floor = 1e-8 * static_cast<double>(target.size(1));
    // The batch mean: this group's share of the sum over the whole batch.
    const auto group_newton_loss = (error / (target.pow(2).sum(1) + floor)).sum() / options_.batch;
    newton_loss += group_newton_loss.item<double>();
    loss = loss + options_.newton_weight * group_newton_loss;
  }
  return loss;
}

void MetaTrainer::take_gradient_step(torch::Tensor loss, TrainStepStats& stats) {
  stats.loss = processes_.sum(loss.item<double>());
  adam_->zero_grad();
  loss.backward();
  sum_gradients_over_processes();
  stats.gradient_norm = torch::nn::utils::clip_grad_norm_(model_->parameters(), options_.clip_norm);
  stats.skipped = !std::isfinite(stats.loss) || !std::isfinite(stats.gradient_norm);
  if (!stats.skipped) {
    adam_->step();
    // The decay ramps up as min(d, (1 + t)/(10 + t)) after t steps (the num_updates rule of
    // TensorFlow's ExponentialMovingAverage), so a short run from scratch forgets its random start.
    const double t = step_;
    if (average_) average_->update(model_, std::min(options_.average_decay, (1.0 + t) / (10.0 + t)));
  }
}

void MetaTrainer::probe_step(const std::vector<int>& order, TrainStepStats& stats) {
  std::vector<std::unique_ptr<ProbeLoss>> losses;
  std::vector<torch::Tensor> gradients, masks;
  for (const int e : order) {
    TrainingEnv& env = *pool_[e];
    StepProblem problem(env.objective(), env.dirichlet());
    VecX g;
    problem.value_gradient(env.acceleration(), g);
    losses.push_back(
        std::make_unique<ProbeLoss>(problem, env.acceleration(), g, options_.probe, &env.reference_acceleration()));
    gradients.push_back(to_coordinate_samples(g, env.grid()));
    masks.push_back(free_mask(env.dirichlet(), env.grid()).expand({3, 1, env.grid().rows, env.grid().cols}));
  }
  const LearnedStep proposal = learned_step(model_, torch::cat(gradients), LearnedState{}, torch::cat(masks));

  // The batch mean of R (1 + log R above 1, as the energy loss), this process's share.
  torch::Tensor loss = torch::zeros({}, torch::kFloat64);
  double ratio_sum = 0.0, baseline_sum = 0.0;
  int counted = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const ProbeLoss& probe = *losses[i];
    if (!probe.defined()) continue;
    const torch::Tensor delta = gate_coordinates(proposal.delta.narrow(0, 3 * i, 3), gradients[i]);
    const torch::Tensor r = probe.remaining(probe.free_dofs(delta));
    const double value = r.item<double>();
    if (!std::isfinite(value)) continue;
    loss = loss + (value <= 1.0 ? r : 1.0 + torch::log(r)) / options_.batch;
    ratio_sum += value;
    baseline_sum += probe.remaining_without_probe();
    ++counted;
  }
  take_gradient_step(loss, stats);

  // Each environment moves on along Newton's solution to its next time step.
  for (const int e : order) {
    TrainingEnv& env = *pool_[e];
    env.acceleration() = env.reference_acceleration();
    while (!env.finish_iteration()) {
    }
  }
  double counts[3] = {ratio_sum, baseline_sum, static_cast<double>(counted)};
  processes_.sum(counts, 3);
  stats.mean_ratio = counts[2] > 0 ? counts[0] / counts[2] : NAN;
  stats.ratio_without_probe = counts[2] > 0 ? counts[1] / counts[2] : NAN;
}

void MetaTrainer::write_environments(torch::serialize::OutputArchive& archive) const {
  for (std::size_t e = 0; e < pool_.size(); ++e) {
    if (!pool_[e]) continue;
    const auto tensors = pool_[e]->state_tensors();
    for (std::size_t k = 0; k < tensors.size(); ++k)
      archive.write(environment_key(static_cast<int>(e), static_cast<int>(k)), tensors[k]);
  }
}

void MetaTrainer::save_checkpoint(const std::string& path) const {
  // The other processes' environments, as archives gathered on rank 0.
  std::vector<std::string> shares;
  if (processes_.size() > 1) {
    torch::serialize::OutputArchive mine;
    write_environments(mine);
    std::ostringstream bytes;
    mine.save_to(bytes);
    shares = processes_.gather(bytes.str());
  }
  if (!processes_.is_root()) return;
  write_atomically(path, [&](const std::string& temporary) {
    torch::serialize::OutputArchive archive;
    archive.write("format", c10::IValue(std::string("fnopt-train-checkpoint")));
    archive.write("signature", c10::IValue(options_.signature()));
    archive.write("step", c10::IValue(static_cast<int64_t>(step_)));
    std::ostringstream rng;
    rng << rng_;
    archive.write("rng", c10::IValue(rng.str()));
    torch::serialize::OutputArchive model, adam;
    model_->save(model);
    adam_->save(adam);
    archive.write("model", model);
    archive.write("adam", adam);
    if (average_) {
      torch::serialize::OutputArchive average;
      average_->model()->save(average);
      archive.write("average", average);
    }
    write_environments(archive);
    for (int rank = 1; rank < static_cast<int>(shares.size()); ++rank) {
      std::istringstream bytes(shares[rank]);
      torch::serialize::InputArchive share;
      share.load_from(bytes);
      for (int e = rank; e < options_.pool.environments; e += processes_.size())
        for (int k = 0;; ++k) {
          const std::string key = environment_key(e, k);
          torch::Tensor tensor;
          if (!share.try_read(key, tensor)) break;
          archive.write(key, tensor);
        }
    }
    archive.save_to(temporary);
  });
}

void MetaTrainer::restore(const std::string& path) {
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const c10::Error&) {
    throw Error(path + ": not a readable training checkpoint");
  }
  c10::IValue value;
  require(archive.try_read("format", value) && value.isString() && value.toStringRef() == "fnopt-train-checkpoint",
          path, "not an fnopt training checkpoint");
  require(archive.try_read("signature", value) && value.isString(), path, "checkpoint without options");
  require(value.toStringRef() == options_.signature(), path,
          "checkpoint made with other options (" + value.toStringRef() + "; now " + options_.signature() + ")");
  archive.read("step", value);
  step_ = static_cast<int>(value.toInt());
  archive.read("rng", value);
  std::istringstream rng(value.toStringRef());
  rng >> rng_;
  torch::serialize::InputArchive model, adam;
  archive.read("model", model);
  archive.read("adam", adam);
  model_->load(model);
  adam_->load(adam);
  if (average_) {
    torch::serialize::InputArchive average;
    if (archive.try_read("average", average))
      average_->model()->load(average);
    else
      average_->reset_to(model_);
  }
  for (int e = 0; e < options_.pool.environments; ++e) {
    if (!owns(e)) {
      pool_.push_back(nullptr);
      continue;
    }
    std::vector<torch::Tensor> tensors(TrainingEnv::kStateTensors);
    for (std::size_t k = 0; k < tensors.size(); ++k) archive.read(environment_key(e, static_cast<int>(k)), tensors[k]);
    // The kept proposals and their gradient differences, if the run that saved it had any. A
    // fresh tensor for each: try_read overwrites a defined tensor in place.
    for (const int k : {TrainingEnv::kStateTensors, TrainingEnv::kStateTensors + 1}) {
      torch::Tensor pairs;
      if (archive.try_read(environment_key(e, k), pairs)) tensors.push_back(pairs);
    }
    pool_.push_back(TrainingEnv::restored(options_.pool, options_.seed, e, tensors));
  }
}

}  // namespace fnopt
