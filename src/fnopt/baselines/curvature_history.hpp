#pragma once
// The memory of the limited-memory quasi-Newton methods (L-BFGS and the prefactored pqn): the
// last m curvature pairs of a minimisation, and the two-loop recursion that applies their
// inverse-Hessian approximation (Nocedal & Wright 2006, Alg. 7.4) on any initial H0.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

// One curvature pair: s = x_{k+1} - x_k, y = g_{k+1} - g_k, rho = 1/(s.y).
struct CurvaturePair {
  VecX s, y;
  double rho = 0.0;
};

// Whether a pair's curvature is clearly positive: s.y above 1e-10 |s| |y| (a cosine; the norms
// in the method's metric, their product given). Pairs of near-zero or negative curvature would
// make the inverse-Hessian model indefinite, so L-BFGS and pqn drop them.
inline bool clearly_positive_curvature(double sy, double norm_product) {
  return std::isfinite(sy) && sy > 1e-10 * norm_product;
}

// direction = -H g, H the L-BFGS inverse Hessian built from `pairs` (oldest first) on the initial
// inverse Hessian H0, which apply_h0(q) applies in place (q <- H0 q). `alphas` is scratch space.
template <class ApplyH0>
void lbfgs_two_loop(const std::vector<const CurvaturePair*>& pairs, ApplyH0&& apply_h0, const VecX& gradient,
                    VecX& direction, std::vector<double>& alphas) {
  const int m = static_cast<int>(pairs.size());
  alphas.resize(m);
  direction = gradient;  // q
  for (int i = m - 1; i >= 0; --i) {
    alphas[i] = pairs[i]->rho * pairs[i]->s.dot(direction);
    direction -= alphas[i] * pairs[i]->y;
  }
  apply_h0(direction);  // r = H0 q
  for (int i = 0; i < m; ++i) {
    const double beta = pairs[i]->rho * pairs[i]->y.dot(direction);
    direction += (alphas[i] - beta) * pairs[i]->s;
  }
  direction = -direction;
}

// The last `capacity` accepted pairs, in a ring (no allocation once every slot has been used).
class CurvatureHistory {
 public:
  explicit CurvatureHistory(int capacity) : ring_(capacity) {}

  void clear() { newest_ = -1, count_ = 0; }
  int size() const { return count_; }
  const CurvaturePair& newest() const { return ring_[newest_]; }

  // Builds the pair from one step and stores it if has_positive_curvature(pair, s.y) says so;
  // a rejected pair leaves the stored ones untouched. Returns whether it was stored (never with
  // capacity 0).
  template <class Test>
  bool push(const VecX& x_old, const VecX& g_old, const VecX& x_new, const VecX& g_new, Test&& has_positive_curvature) {
    if (ring_.empty()) return false;
    candidate_.s = x_new - x_old;
    candidate_.y = g_new - g_old;
    const double sy = candidate_.s.dot(candidate_.y);
    if (!has_positive_curvature(candidate_, sy)) return false;
    candidate_.rho = 1.0 / sy;
    const int capacity = static_cast<int>(ring_.size());
    newest_ = (newest_ + 1) % capacity;
    std::swap(ring_[newest_], candidate_);
    count_ = std::min(count_ + 1, capacity);
    return true;
  }

  // The stored pairs, oldest first (valid until the next push or clear).
  const std::vector<const CurvaturePair*>& oldest_first() {
    const int capacity = static_cast<int>(ring_.size());
    ordered_.clear();
    for (int k = count_ - 1; k >= 0; --k) ordered_.push_back(&ring_[(newest_ - k + capacity) % capacity]);
    return ordered_;
  }

 private:
  std::vector<CurvaturePair> ring_;
  CurvaturePair candidate_;
  int newest_ = -1, count_ = 0;
  std::vector<const CurvaturePair*> ordered_;
};

}  // namespace fnopt
