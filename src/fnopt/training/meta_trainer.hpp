#pragma once
// Self-supervised meta-training of the learned optimizer (docs/design.md §5). One training step:
// draw a batch of environments from the pool, take their masked gradients, run the update
// rule (learned_update.hpp), score the energy after the update (energy_loss.hpp), step AdamW
// on the FNO's parameters, and write each update back into its environment. Checkpoints hold
// everything that the next steps depend on (model, AdamW moments, pool, random state), so a
// killed run resumes where its last checkpoint left it and takes the same next steps.
//
// Data-parallel over processes (mpirun, srun; docs/design.md §12): the batch is drawn by strata,
// position i of the batch from the environments e with e mod batch = i, so process r of P owns
// the environments e with e mod P = r and runs exactly batch/P of every batch. Every process
// draws the same positions (one shared random stream) and starts from the same weights; each
// environment's own randomness depends on its id, so the processes' streams differ. The
// gradients are summed over the processes (one MPI_Allreduce of a flat buffer) before clipping
// and AdamW, so every process takes the same step, the one a single process takes with the
// whole batch (up to the order of the float sums). Checkpoints hold every environment (gathered
// on rank 0, which alone writes them) and resume on any number of processes.
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/learned/learned_update.hpp>
#include <fnopt/parallel/communicator.hpp>
#include <fnopt/training/energy_loss.hpp>
#include <fnopt/training/probe_loss.hpp>
#include <fnopt/training/training_env.hpp>
#include <fnopt/training/weight_average.hpp>

namespace fnopt {

// What a training step scores (docs/design.md §5, §13).
enum class TrainObjective {
  // The learned optimizer's own update: the energy after it (energy_loss.hpp), the shipped model's.
  Energy,
  // The model as fnopt-pqn's probe: at the first iteration of each time step (fresh state), how
  // much of the Newton step's decrease pqn's next iteration misses once it holds the pair
  // measured along the proposal (probe_loss.hpp). The pool then follows the Newton solution of
  // each time step, so its states do not depend on the model.
  Probe
};

struct TrainOptions {
  TrainObjective objective = TrainObjective::Energy;
  // Probe: what the loss scores (probe_loss.hpp): how many pqn iterations after the probe, on the
  // step's quadratic model or its energy; pqn's parameters are fnopt-pqn's defaults.
  ProbeLossOptions probe;
  // Weights a fresh run starts from (a model file of the same shape; empty: random). Not part of
  // the signature: a resumed run takes its weights from the checkpoint.
  std::string initial_model;
  PoolOptions pool;
  FNO2dOptions model = FNO2dOptions().width(32).lifting_channels(64).projection_channels(32);
  int steps = 20000;            // training steps in all
  int batch = 8;                // environments per step (3 FNO samples each)
  double learning_rate = 1e-3;  // AdamW
  double weight_decay = 1e-4;
  int decay_every = 4000;  // the learning rate halves every this many steps
  double clip_norm = 1.0;  // gradient-norm clipping
  // Weight of the auxiliary loss toward the Newton correction: mean over environments of
  // ||delta - delta*||^2 / ||delta*||^2, delta* = a* - a in grid units. The teacher is the
  // energy's own exact minimiser (no data); it gives every vertex a target where the energy
  // loss gives one scalar, which speeds up CPU training. 0 turns it off.
  double newton_weight = 1.0;
  // Score each update where the pool's rule ends after it, past the subspace step, instead of at
  // the raw proposal (energy_loss.hpp; needs pool.subspace > 0). Like the pool's rule it is not
  // part of the signature: a run may be continued with it.
  bool score_after_subspace_step = false;
  // The model a run produces (model.pt, validation) is the moving average of its weights with
  // this decay (weight_average.hpp), ramped up over a run's first steps; 0 gives the trained
  // weights themselves. Averaging does not change the training steps, so it is not part of the
  // signature: a run may be resumed with another decay, and a checkpoint saved without an
  // average starts one at its weights.
  double average_decay = 0.998;
  std::uint64_t seed = 1;

  void validate() const;
  std::string signature() const;  // what a checkpoint must match to be resumed
};

struct TrainStepStats {
  double loss = 0.0;
  double newton_loss = 0.0;          // the auxiliary term, unweighted
  double mean_ratio = 0.0;           // mean r_e (remaining error fraction after the update; Probe: R)
  double ratio_without_probe = NAN;  // Probe: mean R0, pqn's iterations without the probe
  double gradient_norm = 0.0;        // before clipping
  double learning_rate = 0.0;
  int renewed = 0;       // environments replaced after a non-finite update
  bool skipped = false;  // non-finite loss or gradient: no parameter update
};

class MetaTrainer {
 public:
  // A fresh run, or, with `checkpoint`, the run saved there: it then takes exactly the steps
  // the saved run would have taken. Throws Error naming the file if it is unreadable or was
  // made with other options. Collective over `processes`, as are step() and save_checkpoint();
  // the batch must be a multiple of their count.
  explicit MetaTrainer(const TrainOptions& options, const std::string& checkpoint = {},
                       const Communicator& processes = Communicator::self());

  TrainStepStats step();  // the stats of the whole batch, on every process
  int completed_steps() const { return step_; }
  FNO2d& model() { return model_; }  // the trained weights
  // What the run produces: the weight average, or the trained weights if average_decay is 0.
  FNO2d& output_model() { return average_ ? average_->model() : model_; }

  // Rank 0 writes, atomically.
  void save_checkpoint(const std::string& path) const;

 private:
  TrainOptions options_;
  const Communicator& processes_;
  void restore(const std::string& checkpoint);
  bool owns(int environment) const { return environment % processes_.size() == processes_.rank(); }
  // The environments this process owns, as checkpoint entries.
  void write_environments(torch::serialize::OutputArchive& archive) const;
  void sum_gradients_over_processes();
  // One grid size's part of an energy step: its environments, the model's update and the
  // gradients the update saw.
  struct GroupStep {
    EnergyLossBatch batch;
    LearnedStep update;
    std::vector<torch::Tensor> gradients;
  };
  // The model's update and the loss of the environments `members` (of one grid size): their
  // share of the batch's loss; adds their share of the Newton-teacher term to `newton_loss`.
  torch::Tensor group_forward(const std::vector<int>& members, GroupStep& group, double& newton_loss);
  // Backward pass of the batch's loss (this process's share), clipping, AdamW and the average.
  void take_gradient_step(torch::Tensor loss, TrainStepStats& stats);
  // The Probe objective's step on this process's environments `order`.
  void probe_step(const std::vector<int>& order, TrainStepStats& stats);

  FNO2d model_;
  std::unique_ptr<torch::optim::AdamW> adam_;
  std::optional<WeightAverage> average_;
  std::vector<std::unique_ptr<TrainingEnv>> pool_;  // null where another process owns it
  std::mt19937_64 rng_;
  int step_ = 0;
};

}  // namespace fnopt
