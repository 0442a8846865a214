#pragma once
// Minimising the secant model of L over the span of recent search directions.
//
// For directions s_1..s_k (oldest first) and the gradient differences measured along them,
// y_j = g(x_j + s_j) - g(x_j), the quadratic model of L around the current iterate x,
// restricted to steps d = S c, is
//   m(c) = L(x) + c^T S^T g + 1/2 c^T M c,   M = (S^T Y + Y^T S) / 2,
// since y_j = H s_j for a quadratic L, so that M = S^T H S exactly there. Its minimiser
//   c* = -M^+ S^T g
// is the step of a conjugate-direction method over the directions kept (for k = 1 the secant
// step c = -s.g / s.y). M is solved through its eigen-decomposition after Jacobi scaling, on
// the eigenvalues above `kRelativeEigenvalueFloor` of the largest: nearly parallel directions
// make M singular, and that part of the span is dropped rather than amplified.
//
// A pair with s.y <= 0 (L not convex along s at the points measured) is not kept. The
// directions need not come from one method; the learned optimizer feeds its proposals.
// Storage is allocated on the first push of a size and reused (a ring of `capacity` pairs).
#include <Eigen/Dense>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class SecantSubspace {
 public:
  static constexpr int kMaxCapacity = 8;
  static constexpr double kRelativeEigenvalueFloor = 1e-8;
  using Coefficients = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCapacity, 1>;

  explicit SecantSubspace(int capacity);  // 1..kMaxCapacity, Error otherwise

  void clear() { size_ = 0; }
  int size() const { return size_; }
  int capacity() const { return capacity_; }

  // Adds the pair (s, y), dropping the oldest when full. Returns false (and keeps nothing) if
  // s.y <= 0 or is not finite.
  bool push(const VecX& s, const VecX& y);
  // c minimising the model at gradient g (newest direction last); empty if size() == 0.
  Coefficients minimiser(const VecX& gradient) const;
  // step = S c, for c from minimiser() (size() >= 1).
  void combine(const Coefficients& c, VecX& step) const { combine(s_, c, step); }
  // change = Y c: the gradient change along S c for a quadratic L (size() >= 1).
  void combine_changes(const Coefficients& c, VecX& change) const { combine(y_, c, change); }

  // The kept pair j, 0 <= j < size(), oldest first: pushing them again in this order into an
  // empty subspace restores it exactly.
  const VecX& s(int j) const { return s_[index(j)]; }
  const VecX& y(int j) const { return y_[index(j)]; }

 private:
  using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCapacity, kMaxCapacity>;

  int index(int j) const { return (first_ + j) % capacity_; }
  // result = sum_j c_j vectors[j], over the pairs kept in logical order.
  void combine(const std::vector<VecX>& vectors, const Coefficients& c, VecX& result) const;

  int capacity_;
  int size_ = 0, first_ = 0;
  std::vector<VecX> s_, y_;
  // s_i . y_j in logical order (oldest first), kept up to date on every push.
  SmallMatrix sy_;
};

}  // namespace fnopt
