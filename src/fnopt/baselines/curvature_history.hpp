#pragma once
// The memory of the limited-memory quasi-Newton methods: the last m curvature pairs of a
// minimisation, and the two-loop recursion that applies their inverse-Hessian approximation
// (Nocedal & Wright 2006, Alg. 7.4) on any initial H0. One code for every L-BFGS in fnopt: lbfgs
// and pqn (on Eigen vectors), the probe loss of fnopt-pqn's training (on torch tensors, whose
// operations autograd records) and the bounded L-BFGS of the fits (fits/bounded_lbfgs.hpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

// One curvature pair: s = x_{k+1} - x_k, y = g_{k+1} - g_k, rho = 1/(s.y). Scalar is double for
// Eigen vectors, a 0-d tensor for torch tensors.
template <class Vector, class Scalar = double>
struct BasicCurvaturePair {
  Vector s, y;
  Scalar rho{};
};
using CurvaturePair = BasicCurvaturePair<VecX>;

// Whether a pair's curvature is clearly positive: s.y above 1e-10 |s| |y| (a cosine; the norms
// in the method's metric, their product given). Pairs of near-zero or negative curvature would
// make the inverse-Hessian model indefinite, so L-BFGS and pqn drop them.
inline bool clearly_positive_curvature(double sy, double norm_product) {
  return std::isfinite(sy) && sy > 1e-10 * norm_product;
}

// direction = -H g, H the L-BFGS inverse Hessian built from `pairs` (oldest first) on the initial
// inverse Hessian H0, which apply_h0(q) applies (q <- H0 q). `alphas` is scratch space. Every
// update is written out of place (q = q - a y), which Eigen evaluates in place without a
// temporary and torch records for autograd without touching `gradient`.
template <class Pair, class Vector, class Scalar, class ApplyH0>
void lbfgs_two_loop(const std::vector<const Pair*>& pairs, ApplyH0&& apply_h0, const Vector& gradient,
                    Vector& direction, std::vector<Scalar>& alphas) {
  const int m = static_cast<int>(pairs.size());
  alphas.resize(m);
  direction = gradient;  // q
  for (int i = m - 1; i >= 0; --i) {
    alphas[i] = pairs[i]->rho * pairs[i]->s.dot(direction);
    direction = direction - alphas[i] * pairs[i]->y;
  }
  apply_h0(direction);  // r = H0 q
  for (int i = 0; i < m; ++i) {
    const Scalar beta = pairs[i]->rho * pairs[i]->y.dot(direction);
    direction = direction + (alphas[i] - beta) * pairs[i]->s;
  }
  direction = -direction;
}

// The last `capacity` accepted pairs, in a ring (no allocation once every slot has been used).
template <class Vector, class Scalar = double>
class BasicCurvatureHistory {
 public:
  using Pair = BasicCurvaturePair<Vector, Scalar>;

  explicit BasicCurvatureHistory(int capacity) : ring_(capacity) {}

  void clear() { newest_ = -1, count_ = 0; }
  int size() const { return count_; }
  const Pair& newest() const { return ring_[newest_]; }

  // Stores the pair of one step, s = x_new - x_old and y = g_new - g_old, if
  // has_positive_curvature(pair, s.y) says so; a rejected pair leaves the stored ones untouched.
  // Returns whether it was stored (never with capacity 0).
  template <class Test>
  bool push(const Vector& x_old, const Vector& g_old, const Vector& x_new, const Vector& g_new,
            Test&& has_positive_curvature) {
    if (ring_.empty()) return false;
    candidate_.s = x_new - x_old;
    candidate_.y = g_new - g_old;
    return store_candidate(has_positive_curvature);
  }
  // The same for a pair given as its differences.
  template <class Test>
  bool push_pair(const Vector& s, const Vector& y, Test&& has_positive_curvature) {
    if (ring_.empty()) return false;
    candidate_.s = s;
    candidate_.y = y;
    return store_candidate(has_positive_curvature);
  }

  // The stored pairs, oldest first (valid until the next push or clear).
  const std::vector<const Pair*>& oldest_first() {
    const int capacity = static_cast<int>(ring_.size());
    ordered_.clear();
    for (int k = count_ - 1; k >= 0; --k) ordered_.push_back(&ring_[(newest_ - k + capacity) % capacity]);
    return ordered_;
  }

 private:
  template <class Test>
  bool store_candidate(Test&& has_positive_curvature) {
    const Scalar sy = candidate_.s.dot(candidate_.y);
    if (!has_positive_curvature(candidate_, sy)) return false;
    candidate_.rho = 1.0 / sy;
    const int capacity = static_cast<int>(ring_.size());
    newest_ = (newest_ + 1) % capacity;
    std::swap(ring_[newest_], candidate_);
    count_ = std::min(count_ + 1, capacity);
    return true;
  }

  std::vector<Pair> ring_;
  Pair candidate_;
  int newest_ = -1, count_ = 0;
  std::vector<const Pair*> ordered_;
};
using CurvatureHistory = BasicCurvatureHistory<VecX>;

}  // namespace fnopt
