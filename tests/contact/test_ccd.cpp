// CCD: against a naive reference that samples the path finely, for every shape, static and
// moving: no sample before the returned fraction comes within the separation, and (closed forms)
// the distance at the returned fraction is the separation; (conservative advancement) it never
// passes the first sample within the separation.
#include <gtest/gtest.h>

#include <random>

#include <fnopt/contact/ccd.hpp>

namespace fnopt {
namespace {

std::vector<Obstacle> shapes() {
  return {Obstacle::plane(Vec3(0.0, 0.0, -0.2), Vec3(0.2, -0.1, 1.0)), Obstacle::sphere(Vec3(0.1, 0.0, 0.0), 0.35),
          Obstacle::box(Vec3(0.0, 0.1, 0.0), Vec3(0.7, 0.5, 0.4), 0.08),
          Obstacle::capsule(Vec3(-0.4, 0.0, 0.0), Vec3(0.3, 0.1, 0.05), 0.2)};
}

// The first sample of the relative path within the separation, as a fraction (1 if none).
double sampled_first_contact(const Obstacle& o, const Vec3& p0, const Vec3& p1, const Vec3& o0, const Vec3& o1,
                             double separation, int samples) {
  for (int k = 0; k <= samples; ++k) {
    const double s = static_cast<double>(k) / samples;
    if (o.distance(p0 + s * (p1 - p0), o0 + s * (o1 - o0)) <= separation) return s;
  }
  return 1.0;
}

TEST(Ccd, SafeFractionAgreesWithFineSampling) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int kSamples = 20000;
  const double separation = 0.01;
  for (const Obstacle& obstacle : shapes()) {
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const Vec3 p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng));
      const bool moving = trial % 2 == 1;
      const Vec3 o0 = Vec3::Zero(), o1 = moving ? Vec3(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)) : Vec3::Zero();
      if (obstacle.distance(p0, o0) <= separation) {
        EXPECT_EQ(safe_fraction(obstacle, p0, p1, o0, o1, separation), 0.0);
        continue;
      }
      const double s = safe_fraction(obstacle, p0, p1, o0, o1, separation);
      const double sampled = sampled_first_contact(obstacle, p0, p1, o0, o1, separation, kSamples);
      ASSERT_GE(s, 0.0);
      ASSERT_LE(s, 1.0);
      // Safe: every sample before s is outside the separation.
      EXPECT_LE(s, sampled + 1e-12) << shape_name(obstacle.shape()) << " trial " << trial;
      if (sampled < 1.0) {
        ++hits;
        // Tight: the first contact is found, not a point well before it.
        EXPECT_GE(s, sampled - 2.0 / kSamples) << shape_name(obstacle.shape()) << " trial " << trial;
        const Vec3 at = p0 + s * (p1 - p0), offset = o0 + s * (o1 - o0);
        EXPECT_NEAR(obstacle.distance(at, offset), separation, 1e-5) << shape_name(obstacle.shape());
      } else {
        ++misses;
        // Between samples a path could graze the shape; otherwise the whole path is safe.
        if (s < 1.0) {
          const Vec3 at = p0 + s * (p1 - p0), offset = o0 + s * (o1 - o0);
          EXPECT_NEAR(obstacle.distance(at, offset), separation, 1e-5) << shape_name(obstacle.shape());
        }
      }
    }
    EXPECT_GT(hits, 20) << shape_name(obstacle.shape());
    EXPECT_GT(misses, 20) << shape_name(obstacle.shape());
  }
}

// Only the relative motion matters: a vertex at rest hit by a moving obstacle is the vertex moving
// the opposite way into the obstacle at rest.
TEST(Ccd, DependsOnlyOnTheRelativeMotion) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Obstacle& obstacle : shapes())
    for (int trial = 0; trial < 50; ++trial) {
      const Vec3 p(u(rng), u(rng), u(rng)), motion(u(rng), u(rng), u(rng));
      EXPECT_NEAR(safe_fraction(obstacle, p, p, Vec3::Zero(), motion, 0.02),
                  safe_fraction(obstacle, p, p - motion, Vec3::Zero(), Vec3::Zero(), 0.02), 1e-12);
    }
}

}  // namespace
}  // namespace fnopt
