#pragma once
// A low-dimensional parameterisation of the handles' paths (docs/design.md §15): per handle, K
// control points c_k of a curve in time whose value is an offset added to the scene's motion,
//   y_s(h) = motion_h(t_{s+1}) + sum_k B_k(t_{s+1}) c_{h,k},   t_{s+1} = (s + 1) dt,
// over the rollout's T = frames - 1 steps, uniform in time on [0, T dt]. The offset and, for the
// spline, its first two derivatives are zero at t = 0, so the cloth, at rest there, is not
// jerked at its first step:
//  * CubicBSpline: the uniform cubic B-spline of the control sequence (0, 0, 0, c_1 .. c_K) on K
//    segments; on segment i at local u in [0, 1] the weights of its four control points are
//    ((1-u)^3, 3u^3 - 6u^2 + 4, -3u^3 + 3u^2 + 3u + 1, u^3)/6. C^2 in time.
//  * PiecewiseLinear: the offset interpolates linearly between 0 at t = 0 and c_k at
//    t = k T dt / K, k = 1 .. K. C^0; its velocity jumps at the control times.
// The chain rule is the transpose of the same weights: dL/dc_{h,k} = sum_s B_k(t_{s+1}) dL/dy_s(h).
#include <vector>

#include <fnopt/scenes/scene.hpp>

namespace fnopt {

enum class HandlePathBasis { CubicBSpline, PiecewiseLinear };

struct HandlePathParams {
  HandlePathBasis basis = HandlePathBasis::CubicBSpline;
  int control_points = 8;  // K per handle

  void validate() const;  // throws Error("control_points", ...) below 1
};

// control[h][k]: handle h's control point k (an offset in metres).
using HandleControlPoints = std::vector<std::vector<Vec3>>;

class HandlePath {
 public:
  // The basis on `steps` steps of a scene with `handles` handles.
  HandlePath(const HandlePathParams& params, int steps, int handles);

  int control_points() const { return params_.control_points; }
  int steps() const { return static_cast<int>(weights_.size()); }
  // Zero offsets: the scene's own motion.
  HandleControlPoints zero_control_points() const;
  // The offsets sum_k B_k(t_{s+1}) c_{h,k}, per step and handle; throws Error("control points",
  // ...) for a wrong shape.
  std::vector<std::vector<Vec3>> offsets(const HandleControlPoints& control) const;
  // The targets y_s(h): the scene's motion plus the offsets (same errors, and for a scene with
  // another handle count).
  std::vector<std::vector<Vec3>> targets(const ResolvedScene& scene, const HandleControlPoints& control) const;
  // dL/dc from dL/dy (RolloutGradient::handle_targets); throws Error("handle gradient", ...) for
  // a wrong shape.
  HandleControlPoints control_gradient(const std::vector<std::vector<Vec3>>& target_gradient) const;

 private:
  struct Weight {
    int point;  // k, 0-based
    double value;
  };
  void check_control(const HandleControlPoints& control) const;

  HandlePathParams params_;
  int handles_;
  std::vector<std::vector<Weight>> weights_;  // per step, the nonzero B_k(t_{s+1})
};

}  // namespace fnopt
