#pragma once
// One environment of the meta-training pool (docs/design.md §5): an N x N cloth (32^2 by default) with a random
// material (log-uniform over grid-unit ranges), random orientation and gravity direction, the two top corners plus 0-2
// random extra handles on a random smooth motion, and an iteration budget per time step drawn from {1, 3, 10, 30}. The
// learned optimizer iterates on its current time step; when the budget is used the environment advances with its own
// (learned) solution, so the pool visits the states the optimizer itself produces. Each time step is also solved by
// Newton (L* = the exact minimum), or by K pqn iterations where PoolOptions::reference_pqn_iterations says so, which
// makes the training loss scale-free.
// Everything random derives from (seed, id, generation), so an environment is restored from
// its saved state and generation alone.
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/learned/proposal_rule.hpp>

#include <torch/torch.h>

namespace fnopt {

// Log-uniform ranges of the grid-unit quantities (cloth/grid_units.hpp) the pool samples, and of
// the damping c dt (implicit force -c m v; none in `undamped_share` of the environments). They
// cover the default material at 32^2 up to 100^2 with margin (docs/training.md, "The training pool in numbers") and the
// stiffer and softer cases of `fnopt stability`.
struct TrainingRanges {
  double stretch_min = 40.0, stretch_max = 8000.0;
  double shear_min = 0.5, shear_max = 600.0;
  double bend_min = 0.005, bend_max = 20.0;
  double gravity_min = 0.03, gravity_max = 0.6;
  double damping_min = 0.005, damping_max = 0.3;
  double undamped_share = 0.25;

  // Sets the range of one quantity by name (stretch, shear, bend, gravity, damping), as
  // `fnopt train --range` does; throws Error("train.range", "...") naming the valid quantities.
  // Stage 1 of the shipped model trained on stretch 150:8000, shear 0.5:200, undamped share 1.
  void set(const std::string& quantity, double min, double max);
  // "stretch 40:8000, shear 0.5:600, ..., undamped share 0.25", for the log.
  std::string text() const;
  void validate() const;  // throws Error("train.ranges.<field>: ...")
};

struct PoolOptions {
  // The grids of the pool, N x N each: environment e lives on resolutions[e mod count]. With the
  // batch's strata (meta_trainer.hpp) a count that divides the batch gives every batch the same
  // share of each grid; the shipped model trained at 32^2 alone.
  std::vector<int> resolutions{32};
  int environments = 64;
  int max_age = 240;               // time steps before an environment is renewed
  double divergence_strain = 1.0;  // renew when an edge stretches beyond 2x its rest length
  std::vector<int> budgets{1, 3, 10, 30};
  TrainingRanges ranges;
  // How an environment takes the learned proposals (proposal_rule.hpp): 0, as they are (the
  // shipped model's training); K > 0, as fnopt-ss does at inference: the subspace step over the
  // last K proposals, carried across the environment's time steps, and the energy safeguard.
  int subspace = 0;
  // Also put pqn's preconditioned gradient in the subspace before each proposal, as fnopt
  // does (LearnedParams::pqn_direction; needs `subspace`), so the model trains for the directions
  // that complement A^-1 g.
  bool pqn_direction = false;
  // The reference each time step's loss is measured against (L* of energy_loss.hpp): 0, Newton's
  // converged step, the exact minimum (the shipped model's training); K > 0, K iterations of pqn
  // from a_0, an upper bound on L* whose cost does not grow with the material's stiffness (its step
  // is then also the a* that --newton-weight aims at and the probe objective follows). Why:
  // on fine grids Newton's steps on the pool's stiffest materials take most of a training step's
  // time (docs/training.md, "Pools with fine grids").
  int reference_pqn_iterations = 0;

  int resolution_of(int environment) const {
    return resolutions[static_cast<std::size_t>(environment) % resolutions.size()];
  }
  void validate() const;
};

class TrainingEnv {
 public:
  TrainingEnv(const PoolOptions& options, std::uint64_t seed, int id, long generation = 0);
  // An environment as saved by state_tensors(), without first building a fresh one (each build
  // solves a Newton step).
  static std::unique_ptr<TrainingEnv> restored(const PoolOptions& options, std::uint64_t seed, int id,
                                               const std::vector<torch::Tensor>& tensors);

  const Grid& grid() const { return grid_; }
  double dt() const { return dt_; }
  const DirichletSet& dirichlet() const { return dirichlet_; }
  BackwardEulerObjective& objective() { return *objective_; }
  long generation() const { return generation_; }

  // Current iterate of this time step, and its loss bookkeeping.
  VecX& acceleration() { return a_; }
  double reference_loss() const { return reference_loss_; }                       // L* (Newton, or pqn)
  const VecX& reference_acceleration() const { return reference_acceleration_; }  // a* (Newton, or pqn)
  double initial_loss() const { return initial_loss_; }                           // L(a_0)
  int budget() const { return budget_; }
  int used() const { return used_; }

  // Counts one learned iteration; when the budget is used, advances the cloth one step (or
  // renews the environment if it diverged or aged out) and starts the next time step.
  // Returns true if a new time step started.
  bool finish_iteration();
  // Replaces the environment by the next generation (after a non-finite update).
  void renew();

  // Learned-optimizer state carried by the environment.
  torch::Tensor previous_gradient, previous_delta, scale;  // [3,1,R,C], [3,1,R,C], [3,1,1,1]
  // Takes the proposals; its kept proposals carry across time steps and start empty with each
  // generation.
  ProposalRule& rule() { return rule_; }

  // The state that is not derived from (seed, id, generation), for checkpoints: kStateTensors
  // tensors, then the kept proposals and their gradient differences ([K, n] each) if the rule
  // keeps any.
  std::vector<torch::Tensor> state_tensors() const;
  static constexpr int kStateTensors = 7;

 private:
  struct Unbuilt {};
  TrainingEnv(const PoolOptions& options, std::uint64_t seed, int id, Unbuilt);
  void restore(const std::vector<torch::Tensor>& tensors);

  void generate();    // material, pose, handles, motion from (seed, id, generation)
  void begin_step();  // handle targets, a_0, the reference (Newton or pqn), budget
  Vec3 handle_target(int h, double t) const;

  PoolOptions options_;
  std::uint64_t seed_;
  int id_;
  long generation_;
  std::mt19937_64 rng_;
  Grid grid_;
  double dt_ = 1.0 / 60.0;
  std::unique_ptr<BackwardEulerObjective> objective_;
  DirichletSet dirichlet_;
  NewtonOptimizer newton_;
  PqnOptimizer pqn_;  // the reference where reference_pqn_iterations > 0
  ProposalRule rule_;
  std::vector<Vec3> handle_rest_;
  Vec3 pivot_, amplitude_, turn_axis_;
  double frequency_ = 0, phase_ = 0, turn_amplitude_ = 0, turn_frequency_ = 0;
  VecX x_, v_, a_, reference_acceleration_;
  double t_ = 0.0;
  int age_ = 0, budget_ = 1, used_ = 0;
  double reference_loss_ = 0.0, initial_loss_ = 0.0;
};

}  // namespace fnopt
