// The benchmark motions against their formulas (../shared/data/arcsim/README.md), evaluated by
// hand at a few times.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <limits>

#include <fnopt/boundary/trajectory.hpp>
#include "tests/util/error_message.hpp"

namespace fnopt {
namespace {

using testing::throws_error;

const double kSqrt2 = std::sqrt(2.0), kSqrt3 = std::sqrt(3.0);
// The benchmark's two top corners of a 1 m cloth.
const std::vector<Vec3> kCorners = {Vec3(0, 0, 0), Vec3(1, 0, 0)};

void expect_near(const Vec3& actual, const Vec3& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-12)
      << "actual (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

TEST(MotionProfile, RestOutBackOutHold) {
  EXPECT_EQ(motion_profile(-1.0), 0.0);
  EXPECT_EQ(motion_profile(0.0), 0.0);
  EXPECT_EQ(motion_profile(0.5), 0.0);
  EXPECT_NEAR(motion_profile(1.0), 0.5, 1e-15);  // c(0.5) = (1 - cos(pi/2))/2
  EXPECT_NEAR(motion_profile(1.5), 1.0, 1e-15);
  EXPECT_NEAR(motion_profile(2.0), 0.5, 1e-15);
  EXPECT_NEAR(motion_profile(2.5), 0.0, 1e-15);
  EXPECT_NEAR(motion_profile(3.0), 0.5, 1e-15);
  EXPECT_NEAR(motion_profile(3.5), 1.0, 1e-15);
  EXPECT_EQ(motion_profile(6.5), 1.0);
  EXPECT_NEAR(motion_profile(0.75), (1 - std::cos(std::acos(-1.0) / 4)) / 2, 1e-15);
}

TEST(MotionProfile, ContinuousAtEveryPhaseBoundary) {
  for (double t : {0.5, 1.5, 2.5, 3.5})
    EXPECT_NEAR(motion_profile(t - 1e-9), motion_profile(t + 1e-9), 1e-9) << "t = " << t;
}

TEST(Motions, NamesAreTheFifteenThenStatic) {
  const auto names = motion_names();
  ASSERT_EQ(names.size(), 16u);
  EXPECT_EQ(names.front(), "xy_v2");
  EXPECT_EQ(names[14], "rot_h1_opp");
  EXPECT_EQ(names.back(), "static");
  const auto benchmark = benchmark_motion_names();  // compare --motions eval
  ASSERT_EQ(benchmark.size(), 15u);
  EXPECT_EQ(std::count(benchmark.begin(), benchmark.end(), "static"), 0);
  EXPECT_TRUE(std::equal(benchmark.begin(), benchmark.end(), names.begin()));
}

TEST(Motions, XyV2AtOneSecondIsHalfWayAlongTheDiagonal) {
  const auto motion = make_motion("xy_v2", kCorners);
  ASSERT_EQ(motion->handle_count(), 2);
  const Vec3 displacement = 0.5 * Vec3(1, 1, 0) / kSqrt2;  // p(1.0) = 0.5
  expect_near(motion->position(0, 1.0), kCorners[0] + displacement);
  expect_near(motion->position(1, 1.0), kCorners[1] + displacement);
  expect_near(motion->position(0, 0.4), kCorners[0]);  // still at rest
  expect_near(motion->position(1, 2.5), kCorners[1]);  // back at the start
}

TEST(Motions, EveryTranslationEndsOneMetreAlongItsDirection) {
  const std::pair<const char*, Vec3> table[] = {
      {"xy_v2", Vec3(1, 1, 0) / kSqrt2},         {"xy_v2_opp", Vec3(-1, -1, 0) / kSqrt2},
      {"yz_v2", Vec3(0, 1, 1) / kSqrt2},         {"yz_v2_opp", Vec3(0, -1, -1) / kSqrt2},
      {"xz_v2", Vec3(1, 0, -1) / kSqrt2},        {"xyz_v2", Vec3(1, 1, 1) / kSqrt3},
      {"xyz_v2_opp", Vec3(-1, -1, -1) / kSqrt3}, {"xyz_v3", Vec3(1, -1, -1) / kSqrt3},
      {"xyz_v3_opp", Vec3(-1, 1, 1) / kSqrt3},   {"xyz_v4", Vec3(-1, -1, 1) / kSqrt3},
      {"xyz_v4_opp", Vec3(1, 1, -1) / kSqrt3},
  };
  for (const auto& [name, step] : table) {
    SCOPED_TRACE(name);
    const auto motion = make_motion(name, kCorners);
    for (int k = 0; k < 2; ++k) {
      expect_near(motion->position(k, 3.5), kCorners[k] + step);
      expect_near(motion->position(k, 6.5), kCorners[k] + step);
      expect_near(motion->position(k, 3.0), kCorners[k] + 0.5 * step);
    }
  }
}

TEST(Motions, RotH0TurnsHandle1AQuarterAboutHandle0) {
  const auto motion = make_motion("rot_h0", kCorners);
  expect_near(motion->position(0, 3.5), kCorners[0]);
  expect_near(motion->position(1, 3.5), Vec3(0, 1, 0));                    // R_z(+pi/2) (1,0,0)
  expect_near(motion->position(1, 1.0), Vec3(1 / kSqrt2, 1 / kSqrt2, 0));  // theta = pi/4
  expect_near(make_motion("rot_h0_opp", kCorners)->position(1, 3.5), Vec3(0, -1, 0));
}

TEST(Motions, RotH1TurnsHandle0AQuarterAboutHandle1) {
  const auto motion = make_motion("rot_h1", kCorners);
  expect_near(motion->position(1, 3.5), kCorners[1]);
  expect_near(motion->position(0, 3.5), Vec3(1, -1, 0));  // (1,0,0) + R_z(pi/2) (-1,0,0)
  expect_near(make_motion("rot_h1_opp", kCorners)->position(0, 3.5), Vec3(1, 1, 0));
}

TEST(Motions, RotationIsAboutTheVerticalAxisAndKeepsHeights) {
  // corner-center on a 1 m cloth: the centre hangs 0.5 m below the corner.
  const std::vector<Vec3> rest = {Vec3(0, 0, 0), Vec3(0.5, 0, -0.5)};
  const auto motion = make_motion("rot_h0", rest);
  expect_near(motion->position(1, 3.5), Vec3(0, 0.5, -0.5));
  expect_near(motion->position(1, 2.0), Vec3(0.5 / kSqrt2, 0.5 / kSqrt2, -0.5));
}

TEST(Motions, StaticNeverMoves) {
  const auto motion = make_motion("static", kCorners, 2.0);
  for (double t : {0.0, 1.0, 3.5, 100.0})
    for (int k = 0; k < 2; ++k) expect_near(motion->position(k, t), kCorners[k]);
}

TEST(Motions, SpeedFactorPlaysTheFormulaFaster) {
  const auto normal = make_motion("xy_v2", kCorners);
  const auto double_speed = make_motion("xy_v2", kCorners, 2.0);
  // The rest phase ends at 0.25 s instead of 0.5 s; 0.25 s later the handles are where the
  // normal motion has them at 1.0 s (p = 0.5).
  expect_near(double_speed->position(0, 0.25), kCorners[0]);
  expect_near(double_speed->position(0, 0.25 + 0.25), normal->position(0, 1.0));
  expect_near(double_speed->position(1, 0.5), kCorners[1] + 0.5 * Vec3(1, 1, 0) / kSqrt2);
  const auto rotation = make_motion("rot_h0", kCorners, 1.5);
  expect_near(rotation->position(1, 2.0), make_motion("rot_h0", kCorners)->position(1, 3.0));
}

TEST(Motions, SingleHandleTranslatesAndRotH0KeepsIt) {
  const std::vector<Vec3> one = {Vec3(0.5, 0, 0)};
  expect_near(make_motion("yz_v2", one)->position(0, 3.5), one[0] + Vec3(0, 1, 1) / kSqrt2);
  expect_near(make_motion("rot_h0", one)->position(0, 3.5), one[0]);
}

TEST(Motions, RejectsUnknownNamesRotH1OnOneHandleAndBadSpeeds) {
  const std::vector<Vec3> one = {Vec3(0.5, 0, 0)};
  EXPECT_TRUE(throws_error([] { make_motion("xy_v5", kCorners); }, "motion: unknown motion 'xy_v5'"));
  EXPECT_TRUE(throws_error([&] { make_motion("rot_h1", one); }, "motion: rot_h1 keeps handle 1"));
  EXPECT_TRUE(throws_error([&] { make_motion("rot_h1_opp", one); }, "motion: "));
  for (double speed : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    EXPECT_TRUE(throws_error([&] { make_motion("xy_v2", kCorners, speed); }, "speed: "));
}

}  // namespace
}  // namespace fnopt
