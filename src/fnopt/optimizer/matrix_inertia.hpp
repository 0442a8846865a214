#pragma once
// How many eigenvalues of a symmetric sparse matrix are negative, without computing them: by
// Sylvester's law of inertia, the congruence P A P^T = L D L^T (fill-reducing P, no pivoting) has
// as many negative entries in D as A has negative eigenvalues. Used to say whether a stationary
// point of a step's energy is a minimum (none) or a saddle (some) of it (metrics/step_error.hpp).
#include <Eigen/SparseCore>

namespace fnopt {

// The count of negative eigenvalues of the symmetric matrix `a` (its lower triangle is read),
// or -1 if the factorisation meets a zero pivot (a singular leading block: the inertia is then
// not read off D).
int negative_eigenvalue_count(const Eigen::SparseMatrix<double>& a);

}  // namespace fnopt
