#include <fnopt/baselines/pqn.hpp>

#include <cmath>
#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt {

void PqnParams::validate() const {
  require(history >= 0 && history <= 1000, "pqn.history", "must lie in [0, 1000]");
  line_search.validate("pqn");
}

PqnOptimizer::PqnOptimizer(PqnParams params) : params_(validated(params)), history_(params_.history) {}

std::string PqnOptimizer::settings() const {
  std::ostringstream out;
  out << "pqn: history=" << params_.history
      << " (H0 = A^-1, prefactored) backtracking armijo=" << params_.line_search.armijo
      << " shrink=" << params_.line_search.shrink << " max_trials=" << params_.line_search.max_trials;
  return out.str();
}

void PqnOptimizer::use_matrix(const PqnMatrix& matrix) {
  require(given_.factorize(matrix), "pqn", "the given matrix is not positive definite");
  ++given_factorizations_;
  factor_ = &given_;
}

void PqnOptimizer::begin(SmoothProblem& problem, const VecX&, double value, const VecX&) {
  if (const StepProblem* step = problem.step_problem())
    factor_ = &cache_.prepare(*step);
  else if (given_factorizations_ > 0)
    factor_ = &given_;
  else
    throw Error("pqn", "no matrix: use_matrix() must come first on a problem that is not a cloth step");
  history_.clear();
  start_value_ = value;
}

std::optional<SolveStatus> PqnOptimizer::step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) {
  auto apply_inverse = [&](VecX& q) { factor_->solve_in_place(q); };
  double slope = 0.0;
  if (history_.size() > 0) {
    lbfgs_two_loop(history_.oldest_first(), apply_inverse, gradient, direction_, alphas_);
    slope = gradient.dot(direction_);
    if (!(std::isfinite(slope) && slope < 0.0)) history_.clear();  // rounding: restart from -A^-1 g
  }
  if (history_.size() == 0) {
    direction_ = -gradient;
    apply_inverse(direction_);
    slope = gradient.dot(direction_);
  }
  x_old_ = x;
  g_old_ = gradient;
  // The rounding floor of L as in Newton (baselines/newton.cpp): L sums larger terms.
  const double rounding = 1e-12 * (std::abs(value) + std::abs(start_value_));
  if (const auto stop =
          backtracking_line_search(problem, x, value, gradient, direction_, {value, slope, gradient.norm(), rounding},
                                   params_.line_search, line_search_, problem.feasible_step(x, direction_, 1.0)))
    return stop;
  add_pair(x_old_, g_old_, x, gradient);
  return std::nullopt;
}

bool PqnOptimizer::add_pair(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new) {
  return history_.push(x_old, g_old, x_new, g_new, [](const CurvaturePair& pair, double sy) {
    return clearly_positive_curvature(sy, pair.s.norm() * pair.y.norm());
  });
}

PqnFactor& PqnOptimizer::factor() const {
  require(factor_ != nullptr, "pqn", "no factor before the first time step");
  return *factor_;
}

}  // namespace fnopt
