#include <fnopt/metrics/frame_matching.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

double smallest_spacing(const std::vector<double>& times) {
  double spacing = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < times.size(); ++k) {
    require(times[k] >= times[k - 1], "times_s", "frame times must not decrease");
    if (times[k] > times[k - 1]) spacing = std::min(spacing, times[k] - times[k - 1]);
  }
  return spacing;
}

}  // namespace

std::vector<FrameMatch> match_frames(const std::vector<double>& reference_times,
                                     const std::vector<double>& rollout_times, double tolerance) {
  const double spacing = std::min(smallest_spacing(reference_times), smallest_spacing(rollout_times));
  if (!(tolerance > 0.0)) tolerance = std::isfinite(spacing) ? 0.01 * spacing : 1e-9;
  std::vector<FrameMatch> matches;
  std::size_t j = 0;
  for (std::size_t i = 0; i < reference_times.size(); ++i) {
    const double t = reference_times[i];
    while (j < rollout_times.size() && rollout_times[j] < t - tolerance) ++j;
    if (j == rollout_times.size()) break;
    if (std::abs(rollout_times[j] - t) <= tolerance) {
      matches.push_back({static_cast<int>(i), static_cast<int>(j), t});
      ++j;
    }
  }
  return matches;
}

}  // namespace fnopt
