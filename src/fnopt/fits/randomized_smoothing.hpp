#pragma once
// Randomized smoothing of a loss (docs/design.md §15; Suh, Simchowitz, Zhang & Tedrake, "Do
// differentiable simulators give better policy gradients?", ICML 2022): where the rollout is
// nearly chaotic its exact gradient holds only for perturbations far below any useful step, and
// an optimiser stalls on it; the gradient of the smoothed loss
//   L_sigma(x) = E[L(x + sigma e)],   e ~ N(0, I),
// is a guide over perturbations of size sigma. It is estimated by the mean over `samples` draws in
// antithetic pairs (e, -e), of the loss and of its exact gradient at each draw, with the standard
// error of the gradient's mean. The draws are fixed (common random numbers: the same at every x),
// so that the estimate is one smooth deterministic function a line search can work on.
#include <cstdint>
#include <functional>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

struct SmoothingParams {
  double sigma = 0.0;       // the perturbations' standard deviation, in the variables' unit (0: off)
  int samples = 8;          // draws per evaluation, an even number (antithetic pairs)
  std::uint64_t seed = 1;   // of the draws

  bool enabled() const { return sigma > 0.0; }
  void validate() const;  // throws Error naming the field
};

struct SmoothedEvaluation {
  double value = 0.0;     // the mean loss over the draws (+inf if any draw's is)
  VecX gradient;          // the mean gradient
  double standard_error = 0.0;  // of the mean gradient, as a norm: |std over draws| / sqrt(samples)
};

class RandomizedSmoothing {
 public:
  // The draws for variables of this dimension.
  RandomizedSmoothing(const SmoothingParams& params, Eigen::Index dimension);

  // L and its gradient averaged over x + sigma e_k; f(x, gradient) returns L(x) and writes dL/dx.
  SmoothedEvaluation evaluate(const std::function<double(const VecX& x, VecX& gradient)>& f, const VecX& x) const;

 private:
  SmoothingParams params_;
  std::vector<VecX> draws_;  // sigma e_k
};

}  // namespace fnopt
