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
  // Stopped short of its tolerance where L itself cannot resolve progress: the predicted decrease
  // of a Newton step (half the Newton decrement squared, Boyd & Vandenberghe 2004, §9.5.1) is
  // below L's rounding error and no step lowers ||g||. Converged to the precision of L.
  PrecisionLimit,
};

// Converged, to its tolerance or to the precision of the objective.
inline bool is_converged(SolveStatus status) {
  return status == SolveStatus::Converged || status == SolveStatus::PrecisionLimit;
}

inline const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::Converged:
      return "converged";
    case SolveStatus::IterationBudget:
      return "iteration-budget";
    case SolveStatus::LineSearchFailed:
      return "line-search-failed";
    case SolveStatus::FactorizationFailed:
      return "factorization-failed";
    case SolveStatus::NonFinite:
      return "non-finite";
    case SolveStatus::PrecisionLimit:
      return "precision-limit";
  }
  return "unknown";
}

}  // namespace fnopt
