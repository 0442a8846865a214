#pragma once
// Projection of a small symmetric matrix onto the PSD cone (clamp negative eigenvalues to
// zero), the per-stencil step of projected Newton (Teran et al. 2005).
#include <Eigen/Eigenvalues>

namespace fnopt {

template <int D>
Eigen::Matrix<double, D, D> project_psd(const Eigen::Matrix<double, D, D>& H) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> eig(H);
  if (eig.eigenvalues().minCoeff() >= 0.0) return H;
  const Eigen::Matrix<double, D, 1> clamped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace fnopt
