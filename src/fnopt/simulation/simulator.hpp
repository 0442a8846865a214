#pragma once
// A rollout one step at a time (docs/api.md): the state (x, v) of a resolved scene, advanced by
// backward-Euler steps solved by an inner optimizer. The handles follow the scene's trajectory
// or, for closed-loop control, positions given per step. run_rollout (rollout.hpp) is this loop
// over the scene's frames; a Simulator driven by step() reproduces it bit for bit.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/optimizer/step_problem.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {

class SelfContactTerm;

class Simulator {
 public:
  // Starts at rest (x = the grid's rest positions, v = 0, t = 0). `optimizer` is used by step()
  // and must outlive the simulator.
  Simulator(const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options = {});
  Simulator(const Simulator&) = delete;  // its StepProblem points into it
  Simulator& operator=(const Simulator&) = delete;

  // One time step with the handles at the scene's trajectory at t + dt.
  StepRecord step();
  // One time step with the handles at `handle_positions` (one per handle vertex, in the order of
  // handle_vertices()) at t + dt. Throws Error("handles", "...") for a wrong count or a
  // non-finite position.
  StepRecord step(const std::vector<Vec3>& handle_positions);

  // The next step's problem, for an optimizer of one's own: the objective at the current state
  // with the handles prescribed at `handle_positions` (default: the trajectory's at t + dt), and
  // the start a_0 (0 on the free dofs, the prescribed handle accelerations; with obstacles pulled
  // back outside them, StepProblem::make_start_feasible). Valid until the next call that moves the
  // state.
  StepProblem& prepare_step(VecX& start);
  StepProblem& prepare_step(VecX& start, const std::vector<Vec3>& handle_positions);
  // Ends the step prepared last with the acceleration `a` (its handle dofs are taken from the
  // prescription): v += dt a, x += dt v. Returns the step's record (no solve: iterations 0).
  StepRecord commit(const VecX& a);

  // Steers the obstacles: their translations from their rest poses (one per obstacle, in the scene's
  // order) at the end of the next step, instead of their motions' (a collision object driven
  // frame by frame). The step after starts from there. Throws Error("obstacles", ...) for a wrong
  // count or a non-finite offset.
  void set_obstacle_offsets(std::vector<Vec3> end_offsets);
  // The obstacles' translations now (at time()): their motions', or where the last step steered them.
  std::vector<Vec3> obstacle_offsets() const;

  // The handles' positions the scene's trajectory prescribes at time t; past the scene's let-go
  // time, where the handles are free, their vertices' current positions.
  std::vector<Vec3> trajectory_targets(double t) const;
  // Whether the handles have been let go (Scene::let_go): their vertices are free.
  bool handles_released() const { return released_; }

  const VecX& positions() const { return x_; }
  const VecX& velocities() const { return v_; }
  // Positions and velocities, and optionally the steps done (time = steps dt, where the
  // trajectory's handles are read next; the obstacles go back on their motions); throws
  // Error("state", ...) for wrong sizes, non-finite values, negative steps, or, with self-contact, a
  // cloth within its thickness of itself (naming the pair).
  void set_state(const VecX& positions, const VecX& velocities, std::optional<int> steps = std::nullopt);
  double time() const { return time_; }
  int steps_done() const { return steps_; }
  // Whether a step ended non-finite or past the divergence strain (and why); the state is then
  // the last one before it, and step() throws Error("simulation", "...").
  bool diverged() const { return !divergence_.empty(); }
  const std::string& divergence() const { return divergence_; }

  const std::vector<int>& handle_vertices() const { return scene_.handles.vertices; }

 private:
  void refuse_self_contact(const SelfContactTerm& self, const VecX& positions) const;
  StepRecord finish(const VecX& a, const InnerSolveResult& solve, double wall_ms);
  // Frees the handle vertices for a step ending at `step_end` after the scene's let-go time.
  void let_go_if_due(double step_end);
  bool let_go_due(double step_end) const { return scene_.scene.let_go >= 0.0 && step_end > scene_.scene.let_go; }
  void check_running() const;

  ResolvedScene scene_;
  InnerOptimizer* optimizer_;
  RolloutOptions options_;
  BackwardEulerObjective objective_;
  DirichletSet dirichlet_;
  StepProblem problem_;
  VecX x_, v_, a_;
  std::vector<Vec3> targets_;  // the handles' positions of the step prepared last
  // Steered obstacles: the offsets now (where the last step ended them) and at the next step's end;
  // empty where the motions hold.
  std::vector<Vec3> obstacle_offsets_now_, obstacle_offsets_next_;
  double time_ = 0.0;
  int steps_ = 0;
  bool released_ = false;
  std::string divergence_;
};

}  // namespace fnopt
