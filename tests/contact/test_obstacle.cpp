// Obstacle shapes: the signed distance against a brute-force reference (the nearest of many
// surface samples), its gradient and Hessian against finite differences of the distance, the
// Hessian positive semi-definite outside (every shape is convex), and translation by the motions.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/util/error.hpp>
#include "tests/util/finite_difference.hpp"

namespace fnopt {
namespace {

std::vector<Obstacle> shapes() {
  return {Obstacle::plane(Vec3(0.1, -0.2, 0.3), Vec3(0.3, 0.4, 1.2)), Obstacle::sphere(Vec3(0.2, 0.1, -0.3), 0.4),
          Obstacle::box(Vec3(-0.1, 0.2, 0.05), Vec3(0.6, 0.4, 0.3), 0.05),
          Obstacle::capsule(Vec3(-0.3, 0.0, 0.1), Vec3(0.4, 0.2, -0.1), 0.15)};
}

Vec3 random_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Vec3(u(rng), u(rng), u(rng));
}

TEST(Obstacle, GradientAndHessianMatchFiniteDifferencesOfTheDistance) {
  std::mt19937 rng(5);
  const Vec3 offset(0.05, -0.02, 0.03);
  for (const Obstacle& obstacle : shapes()) {
    int checked = 0;
    for (int trial = 0; trial < 200 && checked < 40; ++trial) {
      const Vec3 p = random_point(rng);
      const SignedDistance s = obstacle.evaluate(p, offset);
      if (s.distance < 1e-3) continue;  // outside, where d is smooth except on measure-zero seams
      ++checked;
      EXPECT_NEAR(s.distance, obstacle.distance(p, offset), 1e-14);
      const Vec3 g = testing::central_gradient([&](const Vec3& q) { return obstacle.distance(q, offset); }, p, 1e-6);
      EXPECT_LT((g - s.normal).norm(), 1e-7) << shape_name(obstacle.shape());
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
      const Eigen::MatrixXd H = testing::central_jacobian(
          [&](const Vec3& q) { return Eigen::VectorXd(obstacle.evaluate(q, offset).normal); }, p, 1e-6);
      EXPECT_LT((H - s.hessian).norm(), 1e-5 * (1.0 + s.hessian.norm())) << shape_name(obstacle.shape());
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(s.hessian).eigenvalues().minCoeff(), -1e-12);
    }
    EXPECT_GE(checked, 20);
  }
}

// The distance of a point outside a closed shape is the distance to its nearest surface point.
TEST(Obstacle, DistanceIsTheNearestSurfacePointsOutside) {
  std::mt19937 rng(9);
  for (const Obstacle& obstacle : shapes()) {
    if (obstacle.shape() == ObstacleShape::Plane) continue;
    // Surface samples: points projected onto the zero level set along the gradient.
    std::vector<Vec3> surface;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int s = 0; s < 20000; ++s) {
      Vec3 q = 0.6 * random_point(rng);
      for (int it = 0; it < 30; ++it) {
        const SignedDistance sd = obstacle.evaluate(q, Vec3::Zero());
        q -= sd.distance * sd.normal;
      }
      if (std::abs(obstacle.distance(q, Vec3::Zero())) < 1e-9) surface.push_back(q);
    }
    ASSERT_GT(surface.size(), 5000u);
    for (int trial = 0; trial < 30; ++trial) {
      const Vec3 p = random_point(rng);
      const double d = obstacle.distance(p, Vec3::Zero());
      if (d <= 0.0) continue;
      double nearest = INFINITY;
      for (const Vec3& q : surface) nearest = std::min(nearest, (p - q).norm());
      EXPECT_LE(d, nearest + 1e-9) << shape_name(obstacle.shape());
      EXPECT_GE(d, nearest - 0.03) << shape_name(obstacle.shape());  // the samples' spacing
    }
  }
}

TEST(Obstacle, TranslationMovesTheDistanceField) {
  std::mt19937 rng(2);
  const Vec3 offset(0.3, -0.1, 0.2);
  for (const Obstacle& obstacle : shapes())
    for (int trial = 0; trial < 10; ++trial) {
      const Vec3 p = random_point(rng);
      EXPECT_NEAR(obstacle.distance(p + offset, offset), obstacle.distance(p, Vec3::Zero()), 1e-14);
    }
}

TEST(Obstacle, NamedMotionFollowsTheHandleDisplacement) {
  Obstacle sphere = Obstacle::sphere(Vec3(0.5, 0.2, -0.4), 0.1);
  sphere.with_motion(ObstacleMotion::named("xy_v2", sphere.point()));
  const auto handle = make_motion("xy_v2", {Vec3(0.0, 0.0, 0.0)});
  for (double t : {0.0, 0.7, 1.3, 2.9, 4.0})
    EXPECT_LT((sphere.offset(t) - handle->position(0, t)).norm(), 1e-12) << t;
  EXPECT_TRUE(sphere.moves());
  EXPECT_THROW(ObstacleMotion::named("no_such_motion", Vec3::Zero()), Error);
}

TEST(Obstacle, PathIsInterpolatedLinearlyAndHeldOutside) {
  const std::string file = ::testing::TempDir() + "obstacle_path.csv";
  std::ofstream(file) << "t,x,y,z\n0.5,1,0,0\n1.5,1,2,0\n";
  Obstacle box = Obstacle::box(Vec3(1, 0, 0), Vec3(0.2, 0.2, 0.2), 0.0);
  box.with_motion(ObstacleMotion::path(file));
  EXPECT_LT((box.offset(0.0) - Vec3::Zero()).norm(), 1e-15);
  EXPECT_LT((box.offset(1.0) - Vec3(0, 1, 0)).norm(), 1e-15);
  EXPECT_LT((box.offset(9.0) - Vec3(0, 2, 0)).norm(), 1e-15);
  std::ofstream(file) << "0,1,0,0\n1,nan,0,0\n";
  try {
    ObstacleMotion::path(file);
    FAIL() << "a NaN must be rejected";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "path");
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
  std::remove(file.c_str());
}

TEST(Obstacle, InvalidShapesAreRejectedNamingTheField) {
  auto field = [](auto build) {
    try {
      build();
    } catch (const Error& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field([] { Obstacle::sphere(Vec3::Zero(), -1.0); }), "sphere.radius");
  EXPECT_EQ(field([] { Obstacle::sphere(Vec3::Zero(), 0.0); }), "sphere.radius");
  EXPECT_EQ(field([] { Obstacle::plane(Vec3::Zero(), Vec3::Zero()); }), "plane.normal");
  EXPECT_EQ(field([] { Obstacle::capsule(Vec3::Zero(), Vec3::Zero(), 1.0); }), "capsule.b");
  EXPECT_EQ(field([] { Obstacle::box(Vec3::Zero(), Vec3(1, 1, 1), 0.6); }), "box.rounding");
  EXPECT_EQ(field([] { Obstacle::sphere(Vec3(NAN, 0, 0), 1.0); }), "sphere.center");
  EXPECT_EQ(field([] { Obstacle::sphere(Vec3::Zero(), 1.0).with_friction(-0.1); }), "friction");
}

}  // namespace
}  // namespace fnopt
