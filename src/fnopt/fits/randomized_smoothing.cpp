#include <fnopt/fits/randomized_smoothing.hpp>

#include <cmath>
#include <limits>
#include <random>

#include <fnopt/util/error.hpp>

namespace fnopt {

void SmoothingParams::validate() const {
  require(std::isfinite(sigma) && sigma >= 0.0, "sigma", "must be at least 0 (0: the exact gradient)");
  require(samples >= 2 && samples % 2 == 0, "samples", "must be an even number of at least 2 (antithetic pairs)");
}

RandomizedSmoothing::RandomizedSmoothing(const SmoothingParams& params, Eigen::Index dimension) : params_(params) {
  params.validate();
  std::mt19937_64 random(params.seed);
  std::normal_distribution<double> normal;
  for (int k = 0; k < params.samples / 2; ++k) {
    VecX e(dimension);
    for (Eigen::Index i = 0; i < dimension; ++i) e[i] = params.sigma * normal(random);
    draws_.push_back(e);
    draws_.push_back(-e);
  }
}

SmoothedEvaluation RandomizedSmoothing::evaluate(const std::function<double(const VecX& x, VecX& gradient)>& f,
                                                 const VecX& x) const {
  SmoothedEvaluation out;
  out.gradient = VecX::Zero(x.size());
  VecX gradient, square = VecX::Zero(x.size());
  const double count = static_cast<double>(draws_.size());
  for (const VecX& draw : draws_) {
    const double value = f(x + draw, gradient);
    if (!std::isfinite(value)) {
      out.value = std::numeric_limits<double>::infinity();
      return out;
    }
    out.value += value / count;
    out.gradient += gradient / count;
    square += gradient.cwiseAbs2() / count;
  }
  // The sample variance of each component over the draws, and the mean's standard error.
  const VecX variance = ((square - out.gradient.cwiseAbs2()) * (count / (count - 1.0))).cwiseMax(0.0);
  out.standard_error = std::sqrt(variance.sum() / count);
  return out;
}

}  // namespace fnopt
