#include "baselines/pqn.hpp"

#include <cmath>
#include <sstream>

#include "util/error.hpp"

namespace fnopt {

void PqnParams::validate() const {
  require(history >= 0 && history <= 1000, "pqn.history", "must lie in [0, 1000]");
  line_search.validate("pqn");
}

PqnOptimizer::PqnOptimizer(PqnParams params) : params_(validated(params)), history_(params_.history) {}

std::string PqnOptimizer::settings() const {
  std::ostringstream out;
  out << "pqn: history=" << params_.history << " matrix=" << to_string(params_.matrix)
      << " (H0 = A^-1, prefactored) backtracking armijo=" << params_.line_search.armijo
      << " shrink=" << params_.line_search.shrink << " max_trials=" << params_.line_search.max_trials;
  return out.str();
}

bool PqnOptimizer::MatrixKey::operator==(const MatrixKey& o) const {
  return rows == o.rows && cols == o.cols && spacing == o.spacing && dt == o.dt && stretch == o.stretch &&
         shear == o.shear && bend == o.bend && density == o.density && damping == o.damping &&
         free_index == o.free_index;
}

PqnOptimizer::MatrixKey PqnOptimizer::key_of(const StepProblem& problem) {
  const BackwardEulerObjective& objective = problem.objective();
  const Material& m = objective.material();
  return {problem.grid().rows, problem.grid().cols, problem.grid().spacing, objective.dt(),
          m.stretch,           m.shear,             m.bend,                 m.density,
          m.damping,           problem.dirichlet().free_index()};
}

void PqnOptimizer::prepare_matrix(const StepProblem& problem) {
  MatrixKey key = key_of(problem);
  if (have_factor_ && key == factor_key_) return;
  const PqnMatrix matrix = build_pqn_matrix(problem.objective(), key.free_index, params_.matrix,
                                            problem.grid().rest_positions());
  have_factor_ = factor_.factorize(matrix);
  ++factorizations_;
  // A is the inertia (positive) plus PSD terms: a failure means a non-finite material or dt.
  require(have_factor_, "pqn", "the prefactored matrix is not positive definite (check the material and dt)");
  factor_key_ = std::move(key);
}

void PqnOptimizer::use_matrix(const PqnMatrix& matrix) {
  have_factor_ = factor_.factorize(matrix);
  ++factorizations_;
  require(have_factor_, "pqn", "the given matrix is not positive definite");
  factor_key_ = {};
}

void PqnOptimizer::begin(SmoothProblem& problem, const VecX&, double value, const VecX&) {
  if (const StepProblem* step = problem.step_problem()) prepare_matrix(*step);
  require(have_factor_, "pqn", "no matrix: use_matrix() must come first on a problem that is not a cloth step");
  history_.clear();
  start_value_ = value;
}

std::optional<SolveStatus> PqnOptimizer::step(SmoothProblem& problem, VecX& x, double& value, VecX& gradient) {
  auto apply_inverse = [&](VecX& q) { factor_.solve_in_place(q); };
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
  if (const auto stop = backtracking_line_search(problem, x, value, gradient, direction_,
                                                 {value, slope, gradient.norm(), rounding}, params_.line_search,
                                                 line_search_))
    return stop;
  // Keep only pairs of clearly positive curvature (cosine above 1e-10).
  history_.push(x_old_, g_old_, x, gradient, [](const CurvaturePair& pair, double sy) {
    return std::isfinite(sy) && sy > 1e-10 * pair.s.norm() * pair.y.norm();
  });
  return std::nullopt;
}

}  // namespace fnopt
