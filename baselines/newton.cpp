#include "baselines/newton.hpp"

#include <cmath>

#include "util/error.hpp"

namespace fnopt {

void NewtonParams::validate() const {
  require(relative_tolerance > 0.0 && relative_tolerance < 1.0, "newton.relative_tolerance",
          "must lie in (0, 1)");
  require(max_iterations > 0, "newton.max_iterations", "must be positive");
  require(armijo > 0.0 && armijo < 0.5, "newton.armijo", "must lie in (0, 0.5)");
  require(backtrack > 0.0 && backtrack < 1.0, "newton.backtrack", "must lie in (0, 1)");
  require(max_backtracks > 0, "newton.max_backtracks", "must be positive");
}

NewtonSolver::NewtonSolver(NewtonParams params) : params_(params) { params_.validate(); }

bool NewtonSolver::factorize(const Eigen::SparseMatrix<double>& H) {
  // The objective keeps one matrix per free set, so the symbolic analysis is done once.
  if (analysed_pattern_ != static_cast<const void*>(H.outerIndexPtr()) || llt_.rows() != H.rows()) {
    llt_.analyzePattern(H);
    analysed_pattern_ = H.outerIndexPtr();
  }
  llt_.factorize(H);
  return llt_.info() == Eigen::Success;
}

NewtonResult NewtonSolver::solve(BackwardEulerObjective& objective, const DirichletSet& dirichlet,
                                 VecX& a) {
  const std::vector<int>& free_index = dirichlet.free_index();
  const int vertex_count = dirichlet.vertex_count();
  auto reduce = [&](const VecX& full, VecX& reduced) {
    reduced.resize(3 * dirichlet.free_count());
    for (int v = 0; v < vertex_count; ++v)
      if (free_index[v] >= 0) reduced.segment<3>(3 * free_index[v]) = full.segment<3>(3 * v);
  };

  NewtonResult result;
  double value = objective.value_gradient(a, grad_);
  reduce(grad_, reduced_grad_);
  result.initial_gradient_norm = result.gradient_norm = reduced_grad_.norm();
  result.gradient_norms.push_back(result.gradient_norm);
  const double start_value = value;
  const double tolerance = params_.relative_tolerance * result.initial_gradient_norm;
  bool project = !params_.exact_hessian_first;

  for (;;) {
    result.value = value;
    if (!std::isfinite(value) || !std::isfinite(result.gradient_norm)) {
      result.status = SolveStatus::NonFinite;
      return result;
    }
    if (result.gradient_norm <= tolerance) {
      result.status = SolveStatus::Converged;
      return result;
    }
    if (result.iterations >= params_.max_iterations) {
      result.status = SolveStatus::IterationBudget;
      return result;
    }

    bool factorized = factorize(objective.hessian(a, free_index, project));
    if (!factorized && !project) {
      project = true;
      factorized = factorize(objective.hessian(a, free_index, project));
    }
    if (!factorized) {
      result.status = SolveStatus::FactorizationFailed;
      return result;
    }
    result.projected_iterations += project;
    direction_ = -llt_.solve(reduced_grad_);
    const double slope = reduced_grad_.dot(direction_);

    // Backtracking line search on L(a + alpha d). Close to the minimum, L changes by less than
    // its rounding error; there a step that lowers ||g|| is accepted instead.
    const double rounding = 1e-13 * (std::abs(value) + std::abs(start_value));
    double alpha = 1.0;
    bool accepted = false;
    for (int trial = 0; trial < params_.max_backtracks && !accepted; ++trial, alpha *= params_.backtrack) {
      trial_ = a;
      for (int v = 0; v < vertex_count; ++v)
        if (free_index[v] >= 0) trial_.segment<3>(3 * v) += alpha * direction_.segment<3>(3 * free_index[v]);
      const double trial_value = objective.value_gradient(trial_, trial_grad_);
      if (!std::isfinite(trial_value)) continue;
      const bool armijo = trial_value <= value + params_.armijo * alpha * slope;
      bool flat = false;
      if (!armijo && std::abs(trial_value - value) <= rounding) {
        reduce(trial_grad_, reduced_trial_grad_);
        flat = reduced_trial_grad_.norm() < result.gradient_norm;
      }
      if (armijo || flat) {
        accepted = true;
        a.swap(trial_);
        grad_.swap(trial_grad_);
        value = trial_value;
      }
    }
    if (!accepted) {
      result.status = SolveStatus::LineSearchFailed;
      return result;
    }
    ++result.iterations;
    reduce(grad_, reduced_grad_);
    result.gradient_norm = reduced_grad_.norm();
    result.gradient_norms.push_back(result.gradient_norm);
  }
}

}  // namespace fnopt
