#pragma once
// "fnopt-pqn": the prefactored quasi-Newton method (baselines/pqn.hpp) whose quasi-Newton memory
// also holds what the learned optimizer's proposals measure (docs/design.md §13). pqn's matrix
// A is exact for small in-plane motion; where the step's Hessian H differs from A (compression,
// buckling, large rotations) pqn learns H only through the curvature pairs of its own
// iterates, along directions that A chose. At the iterations the schedule names, the FNO
// proposes a direction p from the gradient first, and the curvature along it is measured:
//   1. p = the FNO's update from the masked gradient alone (first-iteration inputs: a fresh
//      recurrent state), run on a coarse grid (restricted gradient in, prolonged update out)
//      so that one proposal costs a fraction of a fine-grid pass; a coordinate whose gradient
//      is round-off is left out (kCoordinateGate);
//   2. alpha = -g.p / p^T A p, the minimiser along p of the model pqn trusts (p turned round
//      if it points uphill); one gradient evaluation at a + alpha p;
//   3. the pair (alpha p, g(a + alpha p) - g(a)) joins pqn's history, and pqn's iteration
//      follows: its two-loop recursion corrects A along p with the curvature measured there.
// The proposal probes; it does not move the cloth: stepping to a + alpha p instead (when L fell
// there) took the place of a pqn iteration and landed farther from Newton over 390 frames
// (docs/history/results-0.5-experiments.md). The budget N counts pqn's iterations; each proposal adds an FNO pass on
// the coarse grid and one gradient. The history is pqn's: cleared at every time step.
#include <memory>
#include <string>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/cloth/grid_resampling.hpp>
#include <fnopt/fno/fno2d.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>

namespace fnopt {

// A proposal's coordinate whose gradient is below this fraction of the largest coordinate's is
// scaled down in proportion (learned_pqn.cpp).
inline constexpr double kCoordinateGate = 1e-4;

// delta with coordinate c scaled by min(1, |g_c| / (kCoordinateGate max_c' |g_c'|)), delta and
// the gradient g as [3, 1, R, C] coordinate samples (differentiable in delta; training uses it too).
torch::Tensor gate_coordinates(const torch::Tensor& delta, const torch::Tensor& gradient);

struct LearnedPqnParams {
  PqnParams pqn;
  // The FNO's grid: this many vertices along the longer edge, the aspect ratio kept
  // (cloth/grid_resampling.hpp); 0, or a grid not coarser than the step's, runs it on the
  // step's own grid.
  int coarse_size = 32;
  int first = 0;  // the iteration of each time step that takes the first proposal (0-based)
  int every = 0;  // and every `every` iterations after it; 0: one proposal per time step

  void validate() const;  // throws Error("fnopt-pqn.<field>: ...")
  // Whether iteration k (0-based) of a time step takes a proposal.
  bool proposes_at(int iteration) const;
};

class LearnedPqnOptimizer final : public InnerOptimizer {
 public:
  // Loads the model file (Error naming the file if it is missing or not a learned optimizer).
  explicit LearnedPqnOptimizer(const std::string& model_path, LearnedPqnParams params = {});
  LearnedPqnOptimizer(FNO2d model, std::string model_name, LearnedPqnParams params = {});
  ~LearnedPqnOptimizer() override;

  std::string name() const override { return "fnopt-pqn"; }
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

  // Proposals whose pair was measured, and pairs that pqn kept (positive curvature), since
  // construction (tests, diagnostics).
  long proposals() const { return proposals_; }
  long kept_pairs() const { return kept_pairs_; }

 private:
  struct ProposalGrid;
  // Rebuilds the proposal grid (resamplers, handle mask) when the step's grid or handles change.
  void prepare(const StepProblem& problem);
  // direction_ <- the FNO's proposal from `gradient` (fine dofs, zero at handles).
  void propose(const StepProblem& problem, const VecX& gradient);
  // Steps 1-3 of the header up to the pair, at a with its masked gradient.
  void measure_proposal(StepProblem& problem, const VecX& a, const VecX& gradient);

  FNO2d model_;
  std::string model_name_;
  LearnedPqnParams params_;
  PqnOptimizer pqn_;
  std::unique_ptr<ProposalGrid> grid_;
  int iteration_ = 0;
  long proposals_ = 0, kept_pairs_ = 0;
  VecX direction_, trial_, trial_gradient_, coarse_;
};

}  // namespace fnopt
