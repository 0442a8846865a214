// The handle path's bases: offsets that start at rest, reproduce constant control points, and a
// chain rule that is exactly the transpose of the offsets.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/adjoint/handle_path.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr int kSteps = 40;
constexpr int kHandles = 2;

HandleControlPoints constant_points(const HandlePath& path, const Vec3& value) {
  HandleControlPoints points = path.zero_control_points();
  for (auto& handle : points)
    for (Vec3& p : handle) p = value;
  return points;
}

TEST(HandlePath, TheSplineReproducesAConstantOnceItHasRisenAndStartsCubically) {
  const int count = 5;
  const HandlePath path({HandlePathBasis::CubicBSpline, count}, kSteps, kHandles);
  const Vec3 c(0.1, -0.2, 0.3);
  const auto offsets = path.offsets(constant_points(path, c));
  for (int s = 0; s < kSteps; ++s) {
    const double segments = count * (s + 1.0) / kSteps;
    if (segments >= 3.0) {
      EXPECT_LE((offsets[s][1] - c).norm(), 1e-15) << s;
    }
    // On the first segment only c_1 acts, with weight u^3/6: the offset, its velocity and its
    // acceleration are zero at t = 0.
    if (segments <= 1.0) {
      EXPECT_NEAR(offsets[s][0].x(), c.x() * segments * segments * segments / 6.0, 1e-16) << s;
    }
  }
}

TEST(HandlePath, TheLinearPathInterpolatesItsControlPointsFromZero) {
  const int count = 4;
  const HandlePath path({HandlePathBasis::PiecewiseLinear, count}, kSteps, kHandles);
  HandleControlPoints points = path.zero_control_points();
  for (int k = 0; k < count; ++k) points[0][k] = Vec3(k + 1.0, 0.0, 0.0);
  const auto offsets = path.offsets(points);
  for (int s = 0; s < kSteps; ++s)  // c_k = k at t = k T/K, and 0 at t = 0: the offset is K t/T
    EXPECT_NEAR(offsets[s][0].x(), count * (s + 1.0) / kSteps, 1e-14) << s;
}

TEST(HandlePath, TheControlGradientIsTheTransposeOfTheOffsets) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  for (HandlePathBasis basis : {HandlePathBasis::CubicBSpline, HandlePathBasis::PiecewiseLinear}) {
    const HandlePath path({basis, 6}, kSteps, kHandles);
    HandleControlPoints c = path.zero_control_points();
    for (auto& handle : c)
      for (Vec3& p : handle) p = Vec3(normal(random), normal(random), normal(random));
    std::vector<std::vector<Vec3>> y(kSteps, std::vector<Vec3>(kHandles));
    for (auto& step : y)
      for (Vec3& p : step) p = Vec3(normal(random), normal(random), normal(random));
    const auto offsets = path.offsets(c);
    const HandleControlPoints cbar = path.control_gradient(y);
    double lhs = 0.0, rhs = 0.0;
    for (int s = 0; s < kSteps; ++s)
      for (int h = 0; h < kHandles; ++h) lhs += offsets[s][h].dot(y[s][h]);
    for (int h = 0; h < kHandles; ++h)
      for (int k = 0; k < path.control_points(); ++k) rhs += c[h][k].dot(cbar[h][k]);
    EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(lhs));
  }
}

TEST(HandlePath, ZeroOffsetsAreTheScenesMotion) {
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = kSteps + 1;
  scene.speed = 4.0;
  const ResolvedScene resolved = resolve(scene);
  const HandlePath path({}, kSteps, kHandles);
  const auto targets = path.targets(resolved, path.zero_control_points());
  for (int s = 0; s < kSteps; ++s)
    for (int h = 0; h < kHandles; ++h)
      EXPECT_EQ(targets[s][h], resolved.trajectory->position(h, (s + 1) * scene.dt));
}

TEST(HandlePath, WrongShapesAreErrors) {
  EXPECT_THROW(HandlePath({HandlePathBasis::CubicBSpline, 0}, kSteps, kHandles), Error);
  const HandlePath path({}, kSteps, kHandles);
  EXPECT_THROW(path.offsets(HandleControlPoints(kHandles + 1, std::vector<Vec3>(8, Vec3::Zero()))), Error);
  EXPECT_THROW(path.offsets(HandleControlPoints(kHandles, std::vector<Vec3>(7, Vec3::Zero()))), Error);
  EXPECT_THROW(path.control_gradient(std::vector<std::vector<Vec3>>(kSteps - 1, std::vector<Vec3>(kHandles))), Error);
}

}  // namespace
}  // namespace fnopt
