#pragma once
// A rollout: the scene's frames, each one backward-Euler step solved by an inner optimizer
// (docs/design.md §4, §8). The same loop, timing and divergence checks serve every optimizer.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

struct RolloutOptions {
  InnerSolveOptions solve;         // budget and tolerance of every step
  bool warm_start = false;         // start each step from the previous step's acceleration
  double divergence_strain = 3.0;  // an edge longer than (1 + this) x rest means divergence
};

struct StepRecord {
  double wall_ms = 0.0;  // inner solve only: gradients, optimizer, line searches
  SolveStatus status = SolveStatus::IterationBudget;
  int iterations = 0;
  // The objective's evaluations in the solve (StepProblem::evaluations), and those with a gradient.
  int evaluations = 0;
  int gradient_evaluations = 0;
  double initial_loss = 0.0;  // L(a_0)
  double loss = 0.0;          // L(a_N)
  double initial_gradient_norm = 0.0;
  double gradient_norm = 0.0;
  double max_strain = 0.0;  // after the step
  double energy = 0.0;      // kinetic + potential after the step [J]
};

struct RolloutResult {
  Grid grid;
  VecX rest_positions;  // the cloth at rest as the scene places it (ResolvedScene::start_positions)
  std::vector<int> handle_vertices;
  double dt = 0.0;
  std::vector<double> times;                      // [s], frame 0 = the initial state
  std::vector<Eigen::VectorXf> positions;         // per frame, 3 floats per vertex
  std::vector<std::vector<Vec3>> handle_targets;  // per frame, prescribed handle positions
  std::vector<StepRecord> steps;                  // per step (frames - 1 of them)
  bool diverged = false;
  std::string divergence;  // why and when, empty if it did not diverge

  double mean_step_ms() const;
  double max_strain() const;
  int total_iterations() const;
  int converged_steps() const;  // steps whose solve reached its tolerance (is_converged)
};

// Mean wall time of a step after warm-up (plan caches, first-touch memory, the GD curvature
// estimate): skips the first min(10, steps/5) steps; NaN without steps. The ms/frame of every
// comparison table.
double ms_per_frame(const RolloutResult& rollout);

// Called after every step with (steps done, steps in all, the step's record).
using StepCallback = std::function<void(int, int, const StepRecord&)>;

// Runs scene.frames steps from rest on a scene resolved by resolve() (scenes/scene.hpp). A step
// whose solve ends non-finite or whose strain exceeds the divergence limit stops the rollout,
// marked diverged; the frames before it are kept.
RolloutResult run_rollout(const ResolvedScene& resolved, InnerOptimizer& optimizer, const RolloutOptions& options,
                          const StepCallback& on_step = {});

}  // namespace fnopt
