#pragma once
// The interpolation ablation of zero-shot super-resolution (FNOpt's Table 6.4): instead of
// running the 32^2-trained optimizer on the fine grid itself, solve every time step on a
// coarse grid and interpolate. Per time step of a fine R x C grid:
//   1. restrict the state (x_t, v_t) bilinearly to the coarse grid (cloth/grid_resampling.hpp;
//      by default 32 vertices along the longer edge, the aspect ratio kept);
//   2. solve the same backward-Euler step there (same material, dt, gravity; each fine handle
//      becomes the nearest coarse vertex, with the fine handle's prescribed acceleration)
//      with the coarse inner optimizer (the learned one at N = 10, or Newton, ... : any
//      InnerOptimizer, made by a factory, so this file needs no LibTorch);
//   3. prolong the coarse acceleration bilinearly to the fine grid: that is the answer; the
//      fine handles keep their prescribed accelerations (masked as by every optimizer).
// begin_step() does 1-3; the first iterate() returns the answer (with L and the masked
// gradient there) and any further iterate() in the same step stops with Converged. Run it with
// a fine budget of 1 (OptimizerChoice::solve_options does). No safeguard: the fine energy of
// the answer is whatever interpolation gives (that is the ablation).
//
// The coarse objective is built from the fine objective's material, gravity and dt.
#include <functional>
#include <memory>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/cloth/grid_resampling.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>

namespace fnopt {

struct InterpolatedParams {
  int coarse_size = 32;  // vertices along the coarse grid's longer edge (aspect ratio kept)
  int coarse_rows = 0;   // an explicit coarse grid instead (both > 0)
  int coarse_cols = 0;
  InnerSolveOptions coarse_solve{10, 0.0};  // budget and tolerance of the coarse solve

  void validate() const;  // throws Error naming the parameter
};

using InnerOptimizerFactory = std::function<std::unique_ptr<InnerOptimizer>()>;

class InterpolatedOptimizer final : public InnerOptimizer {
 public:
  // Calls `coarse_factory` once here (for the name) and again whenever the coarse problem is
  // rebuilt (another fine grid, handle set, material, gravity or dt), so no coarse state leaks
  // across scenes.
  explicit InterpolatedOptimizer(InnerOptimizerFactory coarse_factory, InterpolatedParams params = {});
  ~InterpolatedOptimizer() override;

  // "<coarse>-interp<K>" (e.g. fnopt-interp32), or "<coarse>-interp<R>x<C>".
  std::string name() const override;
  std::string settings() const override;
  void begin_step(StepProblem& problem, const VecX& a, double value, const VecX& gradient) override;
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override;

  // The coarse grid and the last coarse solve (for tests and diagnostics); the grid is
  // valid after the first begin_step.
  const Grid& coarse_grid() const { return coarse_grid_; }
  const InnerSolveResult& last_coarse_solve() const { return last_coarse_; }

 private:
  struct Coarse;
  void prepare(const StepProblem& problem);

  InnerOptimizerFactory factory_;
  InterpolatedParams params_;
  std::string coarse_name_, coarse_settings_;
  std::unique_ptr<Coarse> coarse_;
  Grid coarse_grid_;
  InnerSolveResult last_coarse_;
  VecX answer_;
  bool pending_ = false;
};

}  // namespace fnopt
