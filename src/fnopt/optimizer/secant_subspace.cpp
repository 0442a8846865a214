#include <fnopt/optimizer/secant_subspace.hpp>

#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

SecantSubspace::SecantSubspace(int capacity) : capacity_(capacity), s_(capacity), y_(capacity) {
  require(capacity >= 1 && capacity <= kMaxCapacity, "subspace",
          "must keep 1 to " + std::to_string(kMaxCapacity) + " directions");
  sy_.resize(capacity, capacity);
}

bool SecantSubspace::push(const VecX& s, const VecX& y) {
  const double curvature = s.dot(y);
  if (!(curvature > 0.0) || !std::isfinite(curvature)) return false;
  if (size_ == capacity_) {  // drop the oldest: shift the products one place up and left
    const int kept = size_ - 1;
    sy_.topLeftCorner(kept, kept) = sy_.bottomRightCorner(kept, kept).eval();
    first_ = index(1);
    --size_;
  }
  const int slot = index(size_);
  s_[slot] = s;
  y_[slot] = y;
  for (int j = 0; j < size_; ++j) {
    sy_(j, size_) = this->s(j).dot(y);
    sy_(size_, j) = s.dot(this->y(j));
  }
  sy_(size_, size_) = curvature;
  ++size_;
  return true;
}

SecantSubspace::Coefficients SecantSubspace::minimiser(const VecX& gradient) const {
  const int k = size_;
  Coefficients rhs(k), scale(k);
  for (int j = 0; j < k; ++j) {
    rhs(j) = -s(j).dot(gradient);
    scale(j) = 1.0 / std::sqrt(sy_(j, j));  // Jacobi scaling: unit curvature along each s_j
  }
  const SmallMatrix top = sy_.topLeftCorner(k, k);
  const SmallMatrix model = scale.asDiagonal() * (0.5 * (top + top.transpose())) * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<SmallMatrix> eigen(model);
  const Coefficients& values = eigen.eigenvalues();
  const double floor = kRelativeEigenvalueFloor * values.maxCoeff();
  Coefficients projected = eigen.eigenvectors().transpose() * scale.asDiagonal() * rhs;
  for (int j = 0; j < k; ++j) projected(j) = values(j) > floor ? projected(j) / values(j) : 0.0;
  return scale.asDiagonal() * (eigen.eigenvectors() * projected);
}

void SecantSubspace::combine(const std::vector<VecX>& vectors, const Coefficients& c, VecX& result) const {
  result.setZero(vectors[index(0)].size());
  for (int j = 0; j < size_; ++j) result.noalias() += c(j) * vectors[index(j)];
}

}  // namespace fnopt
