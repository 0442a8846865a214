#pragma once
// The per-step optimisation error of docs/design.md §8, which isolates an inner optimizer from the
// divergence of its own trajectory: from the SAME state,
//   e_step = (L(a_N) - L(a*)) / (L(a_0) - L(a*)),
// a_0 the start (a = 0 on the free dofs, the handles' prescribed accelerations), a_N the
// method's iterate after its budget, a* the Newton step converged to ||g|| <= 1e-9 ||g_0||.
// 0 is exact, 1 is no progress, > 1 is worse than not moving. It can be slightly negative: the
// step objective is not convex (compressed, buckling cloth), and a method may end in a lower
// local minimum than the one Newton converged to.
//
// The states are sampled from a REFERENCE trajectory (the Newton rollout of the scene, so every
// method is measured on the same, realistic states): `samples` steps spread evenly over the
// rollout; the state of frame t is x_t and v_t = (x_t - x_{t-1})/dt (v_0 = 0), exactly the
// backward-Euler velocity up to the file's float rounding. The Newton solves are done once, in
// the constructor, optionally each with the inertia of the exact Hessian where it ends (an LDL^T
// factorisation: whether Newton's step is a minimum or a saddle of L); evaluate() then costs one
// method solve per sample.
#include <memory>
#include <vector>

#include <fnopt/boundary/dirichlet.hpp>
#include <fnopt/objective/backward_euler.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

struct StepErrorSample {
  int step = 0;                // the state is frame `step`; the solved step goes to step + 1
  double initial_value = 0.0;  // L(a_0)
  double newton_value = 0.0;   // L(a*)
  double method_value = 0.0;   // L(a_N)
  double error = 0.0;          // as above; +inf if the method went non-finite
  SolveStatus status = SolveStatus::IterationBudget;
  // Negative eigenvalues of the exact Hessian of L at a* (free dofs): 0 where Newton's step ends
  // at a local minimum, > 0 at a saddle, where a method can end lower (a negative error); -1 if
  // not counted (the bench was not asked to) or not readable (a zero pivot).
  int newton_negative_eigenvalues = -1;
  // What Newton's step from this state cost: its iterations and products with the exact Hessian
  // (the hard states of a reference are where these are large).
  int newton_iterations = 0;
  long newton_cg_products = 0;
};

struct StepErrorSummary {
  std::vector<StepErrorSample> samples;
  double mean = 0.0;  // arithmetic mean of the errors
  double median = 0.0;
  int newton_saddles() const;  // samples where Newton's step ends at a saddle of L
};

class StepErrorBench {
 public:
  // `reference` must hold a frame every scene.dt from t = 0 (an fnopt rollout of `scene`);
  // throws Error otherwise. Uses the scene's material, handles and trajectory. With
  // count_negative_eigenvalues, also the inertia of the exact Hessian where each Newton step ends:
  // one simplicial LDL^T per sample, seconds each at 100^2, so only where it is asked for.
  StepErrorBench(const Scene& scene, const TrajectoryFrames& reference, int samples,
                 bool count_negative_eigenvalues = false);
  ~StepErrorBench();
  StepErrorBench(const StepErrorBench&) = delete;  // its StepProblem points into it
  StepErrorBench& operator=(const StepErrorBench&) = delete;

  // Solves every sampled step with `method` (a = 0 start, the given budget) and compares.
  StepErrorSummary evaluate(InnerOptimizer& method, const InnerSolveOptions& options);

  const std::vector<int>& steps() const { return steps_; }

 private:
  struct State {
    VecX x, v;
    double time = 0.0;  // t of the step's start (poses moving obstacles)
    std::vector<Vec3> targets;
    double newton_value = 0.0;
    int newton_negative_eigenvalues = -1;
    int newton_iterations = 0;
    long newton_cg_products = 0;
  };
  Grid grid_;
  std::unique_ptr<BackwardEulerObjective> objective_;
  DirichletSet dirichlet_;
  std::unique_ptr<StepProblem> problem_;
  double dt_ = 0.0;
  std::vector<int> steps_;
  std::vector<State> states_;
};

}  // namespace fnopt
