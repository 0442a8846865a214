#include "baselines/newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "optimizer/line_search.hpp"
#include "util/error.hpp"
#include "util/serial_openmp_scope.hpp"

namespace fnopt {

void NewtonParams::validate() const {
  line_search().validate("newton");
  require(forcing_cap > 0.0 && forcing_cap < 1.0, "newton.forcing_cap", "must lie in (0, 1)");
  require(max_cg_iterations >= 0, "newton.max_cg_iterations", "must not be negative");
  require(max_shift >= 0.0, "newton.max_shift", "must not be negative");
  require(shift_growth > 1.0, "newton.shift_growth", "must be greater than 1");
  require(max_slow_shifted_iterations >= 0, "newton.max_slow_shifted_iterations", "must not be negative");
  require(slow_shift_progress > 0.0 && slow_shift_progress < 1.0, "newton.slow_shift_progress",
          "must lie in (0, 1)");
  require(max_pqn_cg_iterations > 0, "newton.max_pqn_cg_iterations", "must be positive");
}

NewtonOptimizer::NewtonOptimizer(NewtonParams params) : params_(params) {
  params_.validate();
  if (params_.pqn_preconditioner) pqn_ = std::make_unique<PqnFactorCache>(PqnMatrixKind::Isotropic);
  // An indefinite Hessian is expected (the projected one is used then): CHOLMOD must not print.
  llt_.cholmod().print = 0;
}

std::string NewtonOptimizer::settings() const {
  // Every parameter: the string is part of compare's reference cache key, so two settings that
  // can give different references must not print the same.
  std::ostringstream out;
  out << "newton: armijo=" << params_.armijo << " backtrack=" << params_.backtrack
      << " max_backtracks=" << params_.max_backtracks << " forcing_cap=" << params_.forcing_cap
      << " max_cg_iterations=" << params_.max_cg_iterations << " max_shift=" << params_.max_shift
      << " shift_growth=" << params_.shift_growth
      << " max_slow_shifted_iterations=" << params_.max_slow_shifted_iterations
      << " slow_shift_progress=" << params_.slow_shift_progress;
  // Only when set, so that the default's string (a cache key of compare's references) stays.
  if (params_.pqn_preconditioner) out << " preconditioner=pqn max_pqn_cg_iterations=" << params_.max_pqn_cg_iterations;
  return out.str();
}

bool NewtonOptimizer::factorize_and_solve(const Eigen::SparseMatrix<double>& H, const VecX& b, long pattern) {
  // The symbolic analysis is redone only when the objective's pattern changes (a new free set,
  // or self-repulsion pairs that the pattern lacked); a shifted copy of H shares H's pattern.
  if (analysed_pattern_ != pattern || llt_.rows() != H.rows()) {
    llt_.analyzePattern(H);
    analysed_pattern_ = pattern;
  }
  ++counters_.factorizations;
  SerialOpenMpScope serial;  // CHOLMOD and its BLAS calls: see util/serial_openmp_scope.hpp
  llt_.factorize(H);
  have_factor_ = llt_.info() == Eigen::Success;
  if (have_factor_) direction_ = llt_.solve(b);
  return have_factor_;
}

template <class Precondition>
NewtonOptimizer::CgOutcome NewtonOptimizer::preconditioned_cg(const Eigen::SparseMatrix<double>& H, double shift,
                                                              const VecX& b, double tolerance, int max_iterations,
                                                              Precondition&& precondition) {
  SerialOpenMpScope serial;  // the factor's triangular solves run in CHOLMOD and BLAS
  direction_.setZero(b.size());
  residual_ = b;
  preconditioned_ = residual_;
  precondition(preconditioned_);
  search_ = preconditioned_;
  double rz = residual_.dot(preconditioned_);
  const double target = tolerance * b.norm();
  for (int k = 0; k < max_iterations; ++k) {
    ++counters_.cg_iterations;
    product_.noalias() = H * search_;
    if (shift != 0.0) product_.array() += shift * inertia_diagonal_.array() * search_.array();
    const double curvature = search_.dot(product_);
    if (curvature <= 0.0) return CgOutcome::NegativeCurvature;
    const double step = rz / curvature;
    direction_ += step * search_;
    residual_ -= step * product_;
    if (residual_.norm() <= target) return CgOutcome::Converged;
    preconditioned_ = residual_;
    precondition(preconditioned_);
    const double rz_next = residual_.dot(preconditioned_);
    search_ = preconditioned_ + (rz_next / rz) * search_;
    rz = rz_next;
  }
  return CgOutcome::TooManyIterations;
}

void NewtonOptimizer::set_inertia_diagonal(StepProblem& problem) {
  const DirichletSet& dirichlet = problem.dirichlet();
  const BackwardEulerObjective& objective = problem.objective();
  inertia_diagonal_.resize(3 * dirichlet.free_count());
  const double dt2 = objective.dt() * objective.dt();
  for (int v = 0; v < dirichlet.vertex_count(); ++v) {
    const int f = dirichlet.free_index()[v];
    if (f >= 0) inertia_diagonal_.segment<3>(3 * f).setConstant(dt2 * objective.masses()[v]);
  }
}

bool NewtonOptimizer::pqn_direction(StepProblem& problem, const Eigen::SparseMatrix<double>& H, double tolerance) {
  PqnFactor& factor = pqn_->prepare(problem);
  auto precondition = [&](VecX& r) { factor.solve_free_in_place(r); };
  const double growth = params_.shift_growth;
  if (!last_shifted_ || shift_ / growth < kMinShift) {
    last_shifted_ = false;
    const CgOutcome outcome = preconditioned_cg(H, 0.0, rhs_, tolerance, params_.max_pqn_cg_iterations, precondition);
    if (outcome == CgOutcome::Converged && rhs_.dot(direction_) > 0.0) return true;
    if (outcome == CgOutcome::TooManyIterations) return false;
  }
  if (params_.max_shift <= 0.0) return false;
  set_inertia_diagonal(problem);
  const double start = last_shifted_ ? shift_ / growth : std::max(kMinShift, shift_ / (growth * growth));
  for (double mu = start; mu <= params_.max_shift; mu *= growth) {
    const CgOutcome outcome = preconditioned_cg(H, mu, rhs_, tolerance, params_.max_pqn_cg_iterations, precondition);
    if (outcome == CgOutcome::TooManyIterations) break;
    if (outcome == CgOutcome::Converged && rhs_.dot(direction_) > 0.0) {
      shift_ = mu;
      last_shifted_ = true;
      ++counters_.shifted_iterations;
      return true;
    }
  }
  last_shifted_ = false;
  return false;
}

bool NewtonOptimizer::shifted_solve(StepProblem& problem, const Eigen::SparseMatrix<double>& H, const VecX& b,
                                     double start) {
  if (params_.max_shift <= 0.0) return false;
  set_inertia_diagonal(problem);
  shifted_ = H;  // one copy; each trial only raises the diagonal to the next mu
  double applied = 0.0;
  for (double mu = start; mu <= params_.max_shift; mu *= params_.shift_growth) {
    shifted_.diagonal() += (mu - applied) * inertia_diagonal_;
    applied = mu;
    if (factorize_and_solve(shifted_, b, problem.objective().hessian_pattern_id()) && b.dot(direction_) > 0.0) {
      shift_ = mu;
      return true;
    }
  }
  return false;
}

bool NewtonOptimizer::newton_direction(StepProblem& problem, const VecX& a, double tolerance) {
  const auto& free_index = problem.dirichlet().free_index();
  const long pattern = problem.objective().hessian_pattern_id();
  const double growth = params_.shift_growth;
  const Eigen::SparseMatrix<double>& H = problem.objective().hessian(a, free_index, false);
  if (pqn_ && pqn_direction(problem, H, tolerance)) return true;
  // After a shifted iteration the exact Hessian is almost surely still indefinite: go straight
  // to the shift search, one level below the last shift, so that the shift decays as the
  // iterate leaves the saddle (each skipped Cholesky of H saves a factorization).
  const bool exact_first = !last_shifted_ || shift_ / growth < kMinShift;
  if (exact_first) {
    last_shifted_ = false;
    if (have_factor_ && params_.max_cg_iterations > 0) {
      const CgOutcome outcome = preconditioned_cg(H, 0.0, rhs_, tolerance, params_.max_cg_iterations,
                                                  [&](VecX& r) { r = llt_.solve(r); });
      if (outcome == CgOutcome::Converged && rhs_.dot(direction_) > 0.0) return true;
    }
    // CG was slow, met negative curvature, or there is no factor yet: refactorize. An
    // indefinite H fails here; then the shifted exact Hessian, and last the projected one.
    if (factorize_and_solve(H, rhs_, pattern) && rhs_.dot(direction_) > 0.0) return true;
  }
  const bool shift_stalled = params_.max_slow_shifted_iterations > 0 &&
                             slow_shifted_iterations_ >= params_.max_slow_shifted_iterations;
  if (shift_stalled) {
    ++counters_.stalled_shifts;
    last_shifted_ = false;  // which also restarts the count at the next iteration
  } else {
    const double start = exact_first ? std::max(kMinShift, shift_ / (growth * growth)) : shift_ / growth;
    last_shifted_ = shifted_solve(problem, H, rhs_, start);
    if (last_shifted_) {
      ++counters_.shifted_iterations;
      return true;
    }
  }
  const Eigen::SparseMatrix<double>& projected = problem.objective().hessian(a, free_index, true);
  if (factorize_and_solve(projected, rhs_, pattern) && rhs_.dot(direction_) > 0.0) {
    ++counters_.projected_iterations;
    return true;
  }
  return false;
}

void NewtonOptimizer::begin_step(StepProblem&, const VecX&, double value, const VecX& gradient) {
  start_value_ = value;
  initial_gradient_norm_ = gradient.norm();
  slow_shifted_iterations_ = 0;
  previous_gradient_norm_ = std::numeric_limits<double>::infinity();  // no iteration of this step yet
}

std::optional<SolveStatus> NewtonOptimizer::iterate(StepProblem& problem, VecX& a, double& value,
                                                    VecX& gradient) {
  const DirichletSet& dirichlet = problem.dirichlet();
  dirichlet.gather_free(gradient, rhs_);
  rhs_ = -rhs_;
  const double gradient_norm = rhs_.norm();
  // The stall guard's count: the last iteration was shifted and gained little.
  const bool slow = last_shifted_ && gradient_norm > params_.slow_shift_progress * previous_gradient_norm_;
  slow_shifted_iterations_ = slow ? slow_shifted_iterations_ + 1 : 0;
  previous_gradient_norm_ = gradient_norm;
  const double forcing = std::min(params_.forcing_cap, gradient_norm / initial_gradient_norm_);
  if (!newton_direction(problem, a, forcing)) return SolveStatus::FactorizationFailed;
  const double slope = -rhs_.dot(direction_);
  dirichlet.scatter_free(direction_, full_direction_);
  // L sums terms larger than itself (inertia, gravity, elastic), so its rounding error is a few
  // hundred ulps of |L| (10^4 stencils): 1e-13 relative still rejected Newton steps at 4e-9 ||g0||.
  const double rounding = 1e-12 * (std::abs(value) + std::abs(start_value_));
  return backtracking_line_search(problem, a, value, gradient, full_direction_,
                                  {value, slope, gradient_norm, rounding}, params_.line_search(), line_search_);
}

}  // namespace fnopt
