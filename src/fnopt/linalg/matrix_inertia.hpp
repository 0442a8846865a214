#pragma once
// How many eigenvalues of a symmetric sparse matrix are negative, without computing them: by
// Sylvester's law of inertia, the congruence P A P^T = L D L^T (fill-reducing P, no pivoting) has
// as many negative entries in D as A has negative eigenvalues. Used to say whether a stationary
// point of a step's energy is a minimum (none) or a saddle (some) of it (studies/compare/step_error.hpp),
// and to leave such a saddle (baselines/newton.hpp, newton-min).
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace fnopt {

// The count of negative eigenvalues of the symmetric matrix `a` (its lower triangle is read),
// or -1 if the factorisation meets a zero pivot (a singular leading block: the inertia is then
// not read off D).
int negative_eigenvalue_count(const Eigen::SparseMatrix<double>& a);

// The same count, from the same factorisation; where it is positive, also a direction of negative
// curvature: z = P^T L^-T s, s the indicator of the negative pivots D_k, so z.Az = sum of those
// D_k < 0 (Moré & Sorensen 1979, "On the use of directions of negative curvature in a modified
// Newton method"). z is left as it was where the count is not positive.
int negative_curvature_direction(const Eigen::SparseMatrix<double>& a, Eigen::VectorXd& z);

}  // namespace fnopt
