#include <fnopt/viewer/vertex_scalars.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fnopt/cloth/grid_resampling.hpp>

namespace fnopt {

namespace {

using Point = Eigen::Vector3f;

Point vertex(const float* positions, int k) { return Eigen::Map<const Point>(positions + 3 * k); }

}  // namespace

std::vector<float> vertex_strain(const TrajectoryFrames& frames, const std::vector<float>& rest) {
  const int R = frames.rows, C = frames.cols, N = R * C;
  std::vector<float> strain(frames.positions.size() * N, -1.0f);
  for (std::size_t t = 0; t < frames.positions.size(); ++t) {
    const float* x = frames.positions[t].data();
    float* s = &strain[t * N];
    auto edge = [&](int a, int b) {
      const float rest_length = (vertex(rest.data(), a) - vertex(rest.data(), b)).norm();
      const float value = (vertex(x, a) - vertex(x, b)).norm() / rest_length - 1.0f;
      s[a] = std::max(s[a], value);
      s[b] = std::max(s[b], value);
    };
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) {
        if (j + 1 < C) edge(i * C + j, i * C + j + 1);
        if (i + 1 < R) edge(i * C + j, (i + 1) * C + j);
      }
  }
  return strain;
}

std::vector<float> vertex_distance(const TrajectoryFrames& frames, const TrajectoryFrames& reference) {
  const int R = frames.rows, C = frames.cols, N = R * C, RR = reference.rows, RC = reference.cols;
  const std::vector<double>& rt = reference.times;
  // A frame at most this far outside the reference's span still counts as inside (rounding).
  const double slack = 1e-6;
  std::vector<float> distance(frames.positions.size() * N, std::numeric_limits<float>::quiet_NaN());
  // Another grid of the same cloth: the reference sampled at this grid's rest positions.
  std::optional<GridResampler> resampler;
  if (RR != R || RC != C) resampler.emplace(Grid::make(RR, RC, 1.0), Grid::make(R, C, 1.0));
  Eigen::VectorXf at_time;
  for (std::size_t t = 0; t < frames.positions.size(); ++t) {
    const double time = frames.times[t];
    if (time < rt.front() - slack || time > rt.back() + slack) continue;
    const std::size_t after =
        std::min<std::size_t>(std::lower_bound(rt.begin(), rt.end(), time) - rt.begin(), rt.size() - 1);
    const std::size_t before = after > 0 ? after - 1 : 0;
    const double span = rt[after] - rt[before];
    const float w = span > 0 ? static_cast<float>(std::clamp((time - rt[before]) / span, 0.0, 1.0)) : 1.0f;
    at_time = (1 - w) * reference.positions[before] + w * reference.positions[after];
    if (resampler) at_time = resampler->apply(at_time.cast<double>()).cast<float>();
    const float* x = frames.positions[t].data();
    for (int k = 0; k < N; ++k) distance[t * N + k] = (vertex(x, k) - vertex(at_time.data(), k)).norm();
  }
  return distance;
}

}  // namespace fnopt
