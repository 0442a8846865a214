#include <fnopt/fits/compass_search.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <fnopt/util/error.hpp>

namespace fnopt {

void CompassSearchParams::validate() const {
  require(std::isfinite(initial_step) && initial_step > 0.0, "initial_step", "must be positive");
  require(std::isfinite(final_step) && final_step > 0.0, "final_step", "must be positive");
  require(max_evaluations >= 1, "max_evaluations", "must be at least 1");
}

CompassSearchResult minimize_by_compass(const CompassObjective& f, const VecX& x0, const VecX& lower, const VecX& upper,
                                        const CompassSearchParams& params) {
  params.validate();
  require(lower.size() == x0.size() && upper.size() == x0.size(), "bounds",
          "expected " + std::to_string(x0.size()) + " lower and upper bounds");
  require((lower.array() <= upper.array()).all(), "bounds", "a lower bound is above its upper bound");

  CompassSearchResult result;
  std::map<std::vector<long long>, double> cache;
  const auto evaluate = [&](const VecX& x) {
    std::vector<long long> key(x.size());
    for (Eigen::Index i = 0; i < x.size(); ++i) key[i] = std::llround(x[i] / (0.25 * params.final_step));
    if (const auto found = cache.find(key); found != cache.end()) return found->second;
    double value = f(x);
    if (!std::isfinite(value)) value = std::numeric_limits<double>::infinity();
    ++result.evaluations;
    return cache.emplace(std::move(key), value).first->second;
  };

  VecX point = x0.cwiseMax(lower).cwiseMin(upper);
  double current = evaluate(point);
  double step = params.initial_step;
  while (step >= params.final_step && result.evaluations < params.max_evaluations) {
    bool improved = false;
    for (Eigen::Index i = 0; i < point.size() && !improved; ++i) {
      for (double sign : {+1.0, -1.0}) {
        if (result.evaluations >= params.max_evaluations) break;
        VecX trial = point;
        trial[i] = std::clamp(point[i] + sign * step, lower[i], upper[i]);
        if (trial[i] == point[i]) continue;
        const double value = evaluate(trial);
        if (value < current) {
          point = trial;
          current = value;
          improved = true;
          break;
        }
      }
    }
    if (!improved) step *= 0.5;
  }
  result.x = point;
  result.value = current;
  result.final_step = step;
  result.converged = step < params.final_step;
  return result;
}

}  // namespace fnopt
