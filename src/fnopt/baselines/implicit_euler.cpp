#include <fnopt/baselines/implicit_euler.hpp>

namespace fnopt {

std::string ImplicitEulerOptimizer::settings() const {
  return "implicit-euler: one linear solve per step, Hessian at x_t (stencils projected to PSD), no line search";
}

void ImplicitEulerOptimizer::begin_step(StepProblem&, const VecX&, double, const VecX&) { solved_ = false; }

std::optional<SolveStatus> ImplicitEulerOptimizer::iterate(StepProblem& problem, VecX& a, double& value,
                                                           VecX& gradient) {
  if (solved_) return SolveStatus::IterationBudget;
  solved_ = true;
  const DirichletSet& dirichlet = problem.dirichlet();
  BackwardEulerObjective& objective = problem.objective();
  // a_0: the free vertices where the step starts (x = x_t), the handles' prescribed values kept.
  const VecX& v = objective.start_velocities();
  for (int k = 0; k < dirichlet.vertex_count(); ++k)
    if (dirichlet.free_index()[k] >= 0) a.segment<3>(3 * k) = -v.segment<3>(3 * k) / objective.dt();
  problem.value_gradient(a, start_gradient_);
  const Eigen::SparseMatrix<double>& H = objective.hessian(a, dirichlet.free_index(), /*project=*/true);
  if (!cholesky_.factorize_matrix(H, objective.hessian_pattern_id())) return SolveStatus::FactorizationFailed;
  dirichlet.gather_free(start_gradient_, rhs_);
  rhs_ = -rhs_;
  cholesky_.solve_in_place(rhs_.data(), static_cast<int>(rhs_.size()), 1);
  for (int k = 0; k < dirichlet.vertex_count(); ++k)
    if (const int f = dirichlet.free_index()[k]; f >= 0) a.segment<3>(3 * k) += rhs_.segment<3>(3 * f);
  value = problem.value_gradient(a, gradient);
  return std::nullopt;
}

}  // namespace fnopt
