#include <fnopt/adjoint/handle_path.hpp>

#include <algorithm>
#include <cmath>

#include <fnopt/util/error.hpp>

namespace fnopt {

void HandlePathParams::validate() const {
  require(control_points >= 1, "control_points", "must be at least 1, got " + std::to_string(control_points));
}

HandlePath::HandlePath(const HandlePathParams& params, int steps, int handles)
    : params_(validated(params)), handles_(handles), weights_(steps) {
  require(steps >= 1, "steps", "must be at least 1");
  const int count = params_.control_points;
  for (int s = 0; s < steps; ++s) {
    const double time = count * static_cast<double>(s + 1) / steps;  // in segments, (0, K]
    std::vector<Weight>& weights = weights_[s];
    if (params_.basis == HandlePathBasis::PiecewiseLinear) {
      const int upper = std::min(count, static_cast<int>(std::ceil(time)));
      const double u = time - (upper - 1);
      weights.push_back({upper - 1, u});
      if (upper >= 2 && u < 1.0) weights.push_back({upper - 2, 1.0 - u});
    } else {
      const int segment = std::min(count - 1, static_cast<int>(std::floor(time)));
      const double u = time - segment;
      const double b[4] = {(1 - u) * (1 - u) * (1 - u) / 6.0, (3 * u * u * u - 6 * u * u + 4) / 6.0,
                           (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6.0, u * u * u / 6.0};
      // Segment i uses the sequence's entries i .. i+3 of (0, 0, 0, c_1 .. c_K): c_k is entry k + 2.
      for (int j = 0; j < 4; ++j) {
        const int point = segment + j - 3;
        if (point >= 0 && b[j] != 0.0) weights.push_back({point, b[j]});
      }
    }
  }
}

HandleControlPoints HandlePath::zero_control_points() const {
  return HandleControlPoints(handles_, std::vector<Vec3>(params_.control_points, Vec3::Zero()));
}

void HandlePath::check_control(const HandleControlPoints& control) const {
  bool ok = static_cast<int>(control.size()) == handles_;
  for (const auto& points : control) ok = ok && static_cast<int>(points.size()) == params_.control_points;
  require(ok, "control points",
          "expected " + std::to_string(handles_) + " handles x " + std::to_string(params_.control_points) + " points");
}

std::vector<std::vector<Vec3>> HandlePath::offsets(const HandleControlPoints& control) const {
  check_control(control);
  std::vector<std::vector<Vec3>> out(steps(), std::vector<Vec3>(handles_, Vec3::Zero()));
  for (int s = 0; s < steps(); ++s)
    for (int h = 0; h < handles_; ++h)
      for (const Weight& w : weights_[s]) out[s][h] += w.value * control[h][w.point];
  return out;
}

std::vector<std::vector<Vec3>> HandlePath::targets(const ResolvedScene& scene,
                                                   const HandleControlPoints& control) const {
  require(static_cast<int>(scene.handles.vertices.size()) == handles_, "control points",
          "the scene has " + std::to_string(scene.handles.vertices.size()) + " handles, the path " +
              std::to_string(handles_));
  std::vector<std::vector<Vec3>> out = offsets(control);
  for (int s = 0; s < steps(); ++s)
    for (int h = 0; h < handles_; ++h) out[s][h] += scene.trajectory->position(h, (s + 1) * scene.scene.dt);
  return out;
}

HandleControlPoints HandlePath::control_gradient(const std::vector<std::vector<Vec3>>& target_gradient) const {
  bool ok = static_cast<int>(target_gradient.size()) == steps();
  for (const auto& row : target_gradient) ok = ok && static_cast<int>(row.size()) == handles_;
  require(ok, "handle gradient",
          "expected " + std::to_string(steps()) + " steps x " + std::to_string(handles_) + " handles");
  HandleControlPoints out = zero_control_points();
  for (int s = 0; s < steps(); ++s)
    for (int h = 0; h < handles_; ++h)
      for (const Weight& w : weights_[s]) out[h][w.point] += w.value * target_gradient[s][h];
  return out;
}

}  // namespace fnopt
