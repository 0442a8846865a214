#pragma once
// Makes a small symmetric matrix positive semi-definite for projected Newton (Teran et al.
// 2005), by replacing each negative eigenvalue with its absolute value rather than with zero
// (the "absolute" projection of saddle-free Newton, Dauphin et al. 2014). Near a saddle of
// compressed, buckling cloth, clamping leaves only the mass term along the escape direction
// and Newton crawls: on the benchmark it left steps unconverged where the absolute value
// converges every step (docs/design.md §6).
#include <Eigen/Eigenvalues>

namespace fnopt {

template <int D>
Eigen::Matrix<double, D, D> project_psd(const Eigen::Matrix<double, D, D>& H) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eig(H);
  if (eig.eigenvalues().minCoeff() >= 0.0) return H;
  const Eigen::Matrix<double, D, 1> clamped = eig.eigenvalues().cwiseAbs();
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace fnopt
