#include <fnopt/baselines/newton.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fnopt/linalg/matrix_inertia.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/serial_openmp_scope.hpp>

namespace fnopt {

void NewtonParams::validate() const {
  require(initial_radius > 0.0, "newton.initial_radius", "must be positive");
  require(accept_ratio >= 0.0 && accept_ratio < shrink_below, "newton.accept_ratio", "must lie in [0, shrink_below)");
  require(shrink_below > 0.0 && shrink_below < grow_above, "newton.shrink_below", "must lie in (0, grow_above)");
  require(grow_above < 1.0, "newton.grow_above", "must be less than 1");
  require(shrink > 0.0 && shrink < 1.0, "newton.shrink", "must lie in (0, 1)");
  require(max_trials > 0, "newton.max_trials", "must be positive");
  require(forcing_cap > 0.0 && forcing_cap < 1.0, "newton.forcing_cap", "must lie in (0, 1)");
  require(max_cg_iterations > 0, "newton.max_cg_iterations", "must be positive");
  require(acceleration_tolerance > 0.0, "newton.acceleration_tolerance", "must be positive");
  require(refactor_cg_iterations >= 0, "newton.refactor_cg_iterations", "must not be negative");
  require(max_saddle_escapes >= 0, "newton.max_saddle_escapes", "must not be negative");
  require(multigrid_from_dofs >= 0, "newton.multigrid_from_dofs", "must not be negative");
  require(bfloat16_factor_from_entries >= 0, "newton.bfloat16_factor_from_entries", "must not be negative");
  multigrid.validate();
}

NewtonOptimizer::NewtonOptimizer(NewtonParams params) : params_(params), multigrid_(params.multigrid) {
  params_.validate();
}

std::string NewtonOptimizer::reference_stop_text() {
  return number_text(reference_solve_options().acceleration_tolerance) + " m/s^2";
}

std::string NewtonOptimizer::settings() const {
  // Every parameter that can change the solution: the string is part of the key of compare's
  // cached references.
  std::ostringstream out;
  out << "newton: trust-region initial_radius=" << params_.initial_radius << " accept_ratio=" << params_.accept_ratio
      << " shrink_below=" << params_.shrink_below << " shrink=" << params_.shrink
      << " grow_above=" << params_.grow_above << " max_trials=" << params_.max_trials
      << " forcing_cap=" << params_.forcing_cap << " acceleration_tolerance=" << params_.acceleration_tolerance
      << " max_cg_iterations=" << params_.max_cg_iterations
      << " refactor_cg_iterations=" << params_.refactor_cg_iterations
      << " reuse_factor_across_steps=" << params_.reuse_factor_across_steps
      << " multigrid_from_dofs=" << params_.multigrid_from_dofs
      << " multigrid_sweeps=" << params_.multigrid.smoothing_sweeps
      << " multigrid_coarsest_dofs=" << params_.multigrid.coarsest_dofs
      << " bfloat16_factor_from_entries=" << params_.bfloat16_factor_from_entries;
  if (params_.escape_saddles) out << " escape_saddles=1 max_saddle_escapes=" << params_.max_saddle_escapes;
  return out.str();
}

bool NewtonOptimizer::factorize_preconditioner(StepProblem& problem, const Eigen::SparseMatrix<double>& projected) {
  const BackwardEulerObjective& objective = problem.objective();
  ++counters_.factorizations;
  if (use_multigrid_) {
    have_factor_ =
        multigrid_.assign(projected, problem.grid(), problem.dirichlet().free_index(), objective.hessian_pattern_id());
    if (have_factor_) return true;
    // A diagonal block's or the coarsest grid's Cholesky failed (P and its Galerkin products are
    // positive definite, but rounding can break that on extreme stiffness): the factor, now.
    hand_over_to_factor();
    use_multigrid_ = false;
  }
  have_factor_ = factor_.factorize_matrix(projected, objective.hessian_pattern_id());
  if (have_factor_)
    single_factor_.assign(
        factor_, static_cast<long>(factor_.cholmod_factor_pointer()->xsize) >= params_.bfloat16_factor_from_entries
                     ? SinglePrecisionFactor::Storage::BFloat16
                     : SinglePrecisionFactor::Storage::Float);
  return have_factor_;
}

void NewtonOptimizer::hand_over_to_factor() {
  if (multigrid_failed_) return;
  multigrid_failed_ = true;
  ++counters_.multigrid_fallbacks;
}

void NewtonOptimizer::begin_step(StepProblem& problem, const VecX&, double value, const VecX& gradient) {
  start_value_ = value;
  initial_gradient_norm_ = gradient.norm();
  radius_ = 0.0;
  escapes_ = 0;
  // With self-contact P is rebuilt at every step's start: the cloth's pairs in range, and their
  // stiffness, change from step to step, and a P without them sizes the first region from a
  // preconditioned gradient far too long along them; the short, cut steps that follow need too few
  // products with H to call for a new factor, and the step can run its whole budget on the old one.
  // Obstacles alone keep the factor (far ones then change nothing, docs/design.md §14).
  if (!params_.reuse_factor_across_steps || problem.objective().self_contact() != nullptr) have_factor_ = false;
}

void NewtonOptimizer::set_metric(const StepProblem& problem) {
  const DirichletSet& dirichlet = problem.dirichlet();
  metric_.resize(3 * static_cast<Eigen::Index>(dirichlet.free_count()));
  for (int v = 0; v < dirichlet.vertex_count(); ++v)
    if (const int f = dirichlet.free_index()[v]; f >= 0)
      metric_.segment<3>(3 * f).setConstant(problem.objective().inertia_weight(v));
}

bool NewtonOptimizer::leave_stationary_point(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  if (!params_.escape_saddles || escapes_ >= params_.max_saddle_escapes) return false;
  const DirichletSet& dirichlet = problem.dirichlet();
  // z (in rhs_, on the free dofs); none at a local minimum (or where the inertia is unreadable).
  if (negative_curvature_direction(problem.objective().hessian(a, dirichlet.free_index(), false), rhs_) <= 0)
    return false;
  if (radius_ == 0.0) set_metric(problem);  // converged at the step's start: no iteration set it
  dirichlet.gather_free(gradient, trial_gradient_);
  const double slope = trial_gradient_.dot(rhs_);
  const double z_norm = std::sqrt((rhs_.array().square() * metric_.array()).sum());
  if (!(z_norm > 0.0)) return false;
  // Downhill along z (either way where g is orthogonal to it), starting at the trust radius.
  double t = (slope > 0.0 ? -1.0 : 1.0) * std::max(radius_, 1e-8) / z_norm;
  const double rounding = 1e-12 * std::abs(value);
  for (int trial = 0; trial < params_.max_trials; ++trial, t *= params_.shrink) {
    dirichlet.scatter_free(t * rhs_, full_step_);
    trial_ = a + full_step_;
    const double trial_value = problem.value_gradient(trial_, trial_gradient_);
    if (std::isfinite(trial_value) && trial_value < value - rounding) {
      a.swap(trial_);
      gradient.swap(trial_gradient_);
      value = trial_value;
      radius_ = std::abs(t) * z_norm;
      ++escapes_;
      ++counters_.saddle_escapes;
      return true;
    }
  }
  return false;
}

bool NewtonOptimizer::preconditioner_is_stale() {
  if (const bool multigrid = rhs_.size() >= params_.multigrid_from_dofs && !multigrid_failed_;
      multigrid != use_multigrid_) {
    use_multigrid_ = multigrid;
    have_factor_ = false;
  }
  return !have_factor_ || preconditioner_rows() != rhs_.size() ||
         last_cg_iterations_ > params_.refactor_cg_iterations;
}

const SymmetricBlockMatrix* NewtonOptimizer::hessian_and_preconditioner(StepProblem& problem, const VecX& a,
                                                                        bool stale) {
  const DirichletSet& dirichlet = problem.dirichlet();
  BackwardEulerObjective& objective = problem.objective();
  if (!stale) return &objective.hessian_blocks(a, dirichlet.free_index(), false);
  const BackwardEulerObjective::HessianPair pair = objective.hessian_pair(a, dirichlet.free_index());
  return factorize_preconditioner(problem, pair.projected) ? &pair.exact : nullptr;
}

double NewtonOptimizer::feasible_trial(StepProblem& problem, const VecX& a) {
  // The trial is the feasible part of the step (the filter every iterate passes, docs/design.md
  // §14), and the ratio judges that point against the model along the same cut step: a trial
  // through the cloth or an obstacle judged at its far end would be accepted there and then pulled
  // back to a point the model never saw, so L could rise from one iterate to the next and the
  // region would grow on a step never taken.
  trial_ = a + full_step_;
  const double fraction = problem.feasible_fraction(a, trial_);
  if (fraction >= 1.0) return 1.0;
  const double cut = problem.pullback() * fraction;
  trial_ = a + cut * full_step_;
  return cut;
}

void NewtonOptimizer::update_radius(double ratio, double cut, const SteihaugResult& sub) {
  // A cut step ends on the feasible set's boundary: the region is sized from the step taken, as
  // from a step that reached the region's own boundary (doubled where the model predicted well),
  // so that the next trials do not sweep again over the contact that cut this one.
  const double taken = cut * sub.step_norm;
  if (ratio < params_.shrink_below)
    radius_ = params_.shrink * taken;
  else if (cut < 1.0)
    radius_ = (ratio > params_.grow_above ? 2.0 : 1.0) * taken;
  else if (ratio > params_.grow_above && sub.on_boundary())
    radius_ *= 2.0;
}

std::optional<SolveStatus> NewtonOptimizer::iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) {
  const DirichletSet& dirichlet = problem.dirichlet();
  dirichlet.gather_free(gradient, rhs_);
  const double gradient_norm = rhs_.norm();
  const bool stale = preconditioner_is_stale();
  BackwardEulerObjective& objective = problem.objective();
  const SymmetricBlockMatrix* exact_hessian = hessian_and_preconditioner(problem, a, stale);
  if (!exact_hessian) return SolveStatus::FactorizationFailed;
  auto precondition = [&](VecX& r) {
    if (use_multigrid_)
      multigrid_.solve_in_place(r);
    else
      single_factor_.solve_in_place(r);
  };
  const bool first = radius_ == 0.0;
  if (first) {  // the step's first iteration: the metric, the preconditioned gradient step's length
    set_metric(problem);
    preconditioned_gradient_ = rhs_;
    precondition(preconditioned_gradient_);
    radius_ = params_.initial_radius * std::sqrt((preconditioned_gradient_.array().square() * metric_.array()).sum());
    if (!(radius_ > 0.0)) return SolveStatus::PrecisionLimit;  // g = 0 to the last bit
  }
  auto multiply = [&](const VecX& p, VecX& out) { exact_hessian->multiply(p, out); };
  // The forcing term, but no finer than the stop needs (the residual acceleration scales with g).
  const double needed = 0.1 * params_.acceleration_tolerance / objective.residual_acceleration(gradient);
  const double forcing = std::min(params_.forcing_cap, std::max(gradient_norm / initial_gradient_norm_, needed));
  // L sums terms larger than itself (inertia, gravity, elastic), so its rounding error is a few
  // hundred ulps of |L| (10^4 stencils); below it a change of L says nothing.
  const double rounding = 1e-12 * (std::abs(value) + std::abs(start_value_));
  // P's factor reused from an earlier iterate is stale once CG needs more than refactor_cg_iterations products: CG
  // stops after refactor_cg_iterations + 1 and its step so far is taken (a truncated Steihaug step, still a descent
  // step inside the region), since the factor is rebuilt at the next iterate and further products would be spent on
  // a preconditioner about to be replaced. Not on the multigrid, where the truncation changed the path through
  // buckling steps (docs/design.md §6).
  const int max_cg_iterations = !stale && !use_multigrid_
                                    ? std::min(params_.max_cg_iterations, params_.refactor_cg_iterations + 1)
                                    : params_.max_cg_iterations;
  last_cg_iterations_ = 0;
  for (int trial = 0; trial < params_.max_trials; ++trial) {
    // A trial after a rejected one solves the same subproblem in a smaller region: on CG's path.
    SteihaugResult sub;
    if (trial == 0 || !steihaug_cg_within(cg_path_, radius_, forcing, step_, sub))
      sub = steihaug_cg(rhs_, radius_, forcing, max_cg_iterations, multiply, precondition, metric_, step_, cg_,
                        &cg_path_, first ? &preconditioned_gradient_ : nullptr);
    counters_.cg_iterations += sub.iterations;
    // A V-cycle built at this iterate that leaves CG at its cap does not precondition this cloth (on very
    // stiff stretch, docs/design.md §6): P's factor from the next iteration on.
    if (use_multigrid_ && stale && sub.end == SteihaugEnd::IterationLimit) hand_over_to_factor();
    last_cg_iterations_ = std::max(last_cg_iterations_, sub.iterations);
    if (sub.end == SteihaugEnd::NegativeCurvature) ++counters_.negative_curvature;
    dirichlet.scatter_free(step_, full_step_);
    const double cut = feasible_trial(problem, a);
    const double trial_value = problem.value_gradient(trial_, trial_gradient_);
    // The model along the step taken, m(s d) = s g.d + s^2 (m(d) - g.d).
    const double slope = cut < 1.0 ? rhs_.dot(step_) : 0.0;
    const double predicted = cut < 1.0 ? -(cut * slope + cut * cut * (sub.model - slope)) : -sub.model;
    bool accept = false;
    if (cut < 1.0 && predicted <= rounding) {
      radius_ = params_.shrink * cut * sub.step_norm;  // a contact right ahead: a shorter step
    } else if (predicted <= rounding) {
      // L cannot judge a step this small: take it if it lowers ||g|| and does not raise L beyond
      // its rounding; otherwise this iterate is a stationary point to the precision of L.
      accept = std::isfinite(trial_value) && trial_value <= value + rounding && trial_gradient_.norm() < gradient_norm;
      if (!accept) return SolveStatus::PrecisionLimit;
    } else {
      const double ratio = std::isfinite(trial_value) ? (value - trial_value) / predicted : -INFINITY;
      update_radius(ratio, cut, sub);
      accept = ratio > params_.accept_ratio;
    }
    if (accept) {
      a.swap(trial_);
      gradient.swap(trial_gradient_);
      value = trial_value;
      return std::nullopt;
    }
    ++counters_.rejected_trials;
  }
  return SolveStatus::LineSearchFailed;
}

}  // namespace fnopt
