#include <fnopt/studies/compare/step_error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/linalg/matrix_inertia.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/median.hpp>

namespace fnopt {

int StepErrorSummary::newton_saddles() const {
  return static_cast<int>(std::count_if(samples.begin(), samples.end(),
                                        [](const StepErrorSample& s) { return s.newton_negative_eigenvalues > 0; }));
}

StepErrorBench::~StepErrorBench() = default;

StepErrorBench::StepErrorBench(const Scene& scene, const TrajectoryFrames& reference, int samples,
                               bool count_negative_eigenvalues) {
  require(samples >= 1, "step-error samples", "must be positive");
  const ResolvedScene setup = resolve(scene);
  grid_ = setup.grid;
  require(reference.rows == grid_.rows && reference.cols == grid_.cols, "step error",
          "the reference trajectory's grid differs from the scene's");
  dt_ = scene.dt;
  const int frames = static_cast<int>(reference.positions.size());
  require(frames >= 2, "step error", "the reference trajectory needs at least two frames");
  for (int t = 0; t < frames; ++t)
    require(std::abs(reference.times[t] - t * dt_) <= 1e-6 * dt_ * std::max(1, t), "step error",
            "the reference must hold a frame every time step (an fnopt rollout of the same scene)");

  objective_ = std::make_unique<BackwardEulerObjective>(grid_, setup.scene.material, scene.dt, setup.scene.gravity,
                                                        setup.scene.obstacles, setup.scene.contact,
                                                        self_contact_of(setup.scene));
  dirichlet_ = DirichletSet(grid_.vertex_count(), setup.handles.vertices);
  problem_ = std::make_unique<StepProblem>(*objective_, dirichlet_);
  const int handle_count = static_cast<int>(setup.handles.vertices.size());

  // Steps 0 .. frames-2 start from a stored state; spread the samples evenly over them.
  const int available = frames - 1;
  samples = std::min(samples, available);
  // The samples are unrelated states: a factor from the previous one is no preconditioner for the
  // next, and the first trust region is sized by it: Newton then takes many times the iterations
  // its rollout took on the same states (docs/design.md §6).
  NewtonParams fresh_factor;
  fresh_factor.reuse_factor_across_steps = false;
  NewtonOptimizer newton(fresh_factor);
  for (int k = 0; k < samples; ++k) {
    const int t = std::min(available - 1, static_cast<int>((k + 0.5) * available / samples));
    if (!steps_.empty() && steps_.back() == t) continue;
    State state;
    state.x = reference.positions[t].cast<double>();
    state.v =
        t > 0 ? VecX((state.x - reference.positions[t - 1].cast<double>()) / dt_) : VecX(VecX::Zero(grid_.dof_count()));
    for (int h = 0; h < handle_count; ++h) state.targets.push_back(setup.trajectory->position(h, (t + 1) * dt_));
    state.time = t * dt_;
    objective_->begin_step(state.x, state.v, state.time);
    VecX a = VecX::Zero(grid_.dof_count());
    dirichlet_.prescribe(a, state.x, state.v, state.targets, dt_);
    const long cg_products_before = newton.counters().cg_iterations;
    const InnerSolveResult newton_result = solve_step(newton, *problem_, a, NewtonOptimizer::reference_solve_options());
    state.newton_value = newton_result.value;
    state.newton_iterations = newton_result.iterations;
    state.newton_cg_products = newton.counters().cg_iterations - cg_products_before;
    if (count_negative_eigenvalues)
      state.newton_negative_eigenvalues =
          negative_eigenvalue_count(objective_->hessian(a, dirichlet_.free_index(), false));
    steps_.push_back(t);
    states_.push_back(std::move(state));
  }
}

StepErrorSummary StepErrorBench::evaluate(InnerOptimizer& method, const InnerSolveOptions& options) {
  StepErrorSummary summary;
  std::vector<double> errors;
  for (std::size_t k = 0; k < states_.size(); ++k) {
    const State& state = states_[k];
    objective_->begin_step(state.x, state.v, state.time);
    VecX a = VecX::Zero(grid_.dof_count());
    dirichlet_.prescribe(a, state.x, state.v, state.targets, dt_);
    const InnerSolveResult result = solve_step(method, *problem_, a, options);
    StepErrorSample sample;
    sample.step = steps_[k];
    sample.initial_value = result.initial_value;
    sample.newton_value = state.newton_value;
    sample.newton_negative_eigenvalues = state.newton_negative_eigenvalues;
    sample.newton_iterations = state.newton_iterations;
    sample.newton_cg_products = state.newton_cg_products;
    sample.method_value = result.value;
    sample.status = result.status;
    const double gap = result.initial_value - state.newton_value;
    sample.error = result.status == SolveStatus::NonFinite || !std::isfinite(result.value)
                       ? std::numeric_limits<double>::infinity()
                       : (result.value - state.newton_value) / gap;
    summary.samples.push_back(sample);
    errors.push_back(sample.error);
  }
  if (errors.empty()) {
    summary.mean = summary.median = std::nan("");
    return summary;
  }
  double sum = 0.0;
  for (double e : errors) sum += e;
  summary.mean = sum / errors.size();
  summary.median = median(std::move(errors));
  return summary;
}

}  // namespace fnopt
