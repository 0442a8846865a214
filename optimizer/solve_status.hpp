#pragma once
// Why an inner solve stopped (polysolve style): every solver reports one of these, never a
// silent stop.
namespace fnopt {

enum class SolveStatus {
  Converged,            // reached its tolerance
  IterationBudget,      // used its iteration budget (the normal end of fixed-budget methods)
  LineSearchFailed,     // no step along a descent direction decreased the objective
  FactorizationFailed,  // the (projected) Hessian could not be factorized
  NonFinite,            // NaN or Inf in the objective, gradient or iterate
};

inline const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::IterationBudget: return "iteration-budget";
    case SolveStatus::LineSearchFailed: return "line-search-failed";
    case SolveStatus::FactorizationFailed: return "factorization-failed";
    case SolveStatus::NonFinite: return "non-finite";
  }
  return "unknown";
}

}  // namespace fnopt
