// Scenes with obstacles, with Newton converging on every step and no frame inside an obstacle:
// a cloth draped over a sphere, a released cloth falling on a table and hanging over its edges, a
// sphere pushed through a hanging cloth, and Coulomb's threshold on an incline (a cloth on a floor
// under gravity tilted by theta, the same as a plane tilted by theta): it sticks where
// tan(theta) < mu and slides where tan(theta) > mu.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

RolloutResult newton_rollout(const Scene& scene) {
  NewtonOptimizer newton;
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  RolloutResult r = run_rollout(resolve(scene), newton, options);
  EXPECT_FALSE(r.diverged) << r.divergence;
  for (std::size_t s = 0; s < r.steps.size(); ++s)
    EXPECT_TRUE(is_converged(r.steps[s].status)) << "step " << s + 1 << ": " << to_string(r.steps[s].status);
  EXPECT_GE(min_obstacle_distance(scene, r.positions), 0.0);
  return r;
}

Scene released_scene(int frames) {
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = frames;
  scene.handles = "none";
  scene.placement = Placement::Horizontal;
  return scene;
}

Vec3 position(const RolloutResult& r, int frame, int vertex) {
  return r.positions[frame].segment<3>(3 * vertex).cast<double>();
}

TEST(ContactScenes, ClothDrapesOverASphere) {
  Scene scene = released_scene(120);
  scene.obstacles = parse_obstacles("sphere center=0,0,-0.3 radius=0.25 friction=0.5");
  const RolloutResult r = newton_rollout(scene);
  const Grid grid = resolve(scene).grid;
  const int centre = grid.index(7, 7), corner = grid.index(0, 0);
  const double reach = scene.contact.thickness + scene.contact.range_fraction * grid.spacing;
  // The middle rests on the top of the sphere; the corners hang below its equator's height.
  EXPECT_LT(scene.obstacles[0].distance(position(r, 120, centre), Vec3::Zero()), reach);
  EXPECT_LT(position(r, 120, corner).z(), -0.3);
}

TEST(ContactScenes, ReleasedClothFallsOnATableAndHangsOverItsEdges) {
  Scene scene = released_scene(90);
  scene.obstacles = parse_obstacles("box center=0,0,-0.3 size=0.6,0.6,0.5 rounding=0.01");  // top at -0.05
  const RolloutResult r = newton_rollout(scene);
  const Grid grid = resolve(scene).grid;
  const double reach = scene.contact.thickness + scene.contact.range_fraction * grid.spacing;
  const Vec3 middle = position(r, 90, grid.index(7, 7));
  EXPECT_NEAR(middle.z(), -0.05 + 0.5 * reach, 0.5 * reach);  // lying on the top
  // The cloth overhangs the 0.6 m table by 0.2 m each side: its edges fall below the top.
  EXPECT_LT(position(r, 90, grid.index(7, 0)).z(), -0.15);
  EXPECT_LT(position(r, 90, grid.index(0, 7)).z(), -0.15);
}

TEST(ContactScenes, ASpherePushedThroughAHangingClothCarriesIt) {
  const std::string file = ::testing::TempDir() + "pushing_sphere.csv";
  std::ofstream(file) << "t,x,y,z\n0.2,0.5,-0.3,-0.55\n1.2,0.5,0.5,-0.55\n";
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = 72;
  scene.motion = "static";
  scene.obstacles = parse_obstacles("sphere center=0.5,-0.3,-0.55 radius=0.15 path=" + file);
  const RolloutResult r = newton_rollout(scene);
  std::remove(file.c_str());
  const Grid grid = resolve(scene).grid;
  // At t = 1.2 s the sphere's front is at y = 0.65: the cloth's middle was carried forward.
  EXPECT_GT(position(r, 72, grid.index(8, 8)).y(), 0.3);
  for (std::size_t f = 0; f < r.positions.size(); ++f)
    EXPECT_GT(min_obstacle_distance(scene.obstacles, r.positions[f].cast<double>(), grid.rows, grid.cols, f * scene.dt),
              0.0);
}

// The cloth's mean x after 1.2 s on a floor (mu = 0.5) with gravity tilted by atan(slope) toward +x.
double slide_on_incline(double slope) {
  Scene scene = released_scene(72);
  scene.material.damping = 0.0;  // no drag: the sliding acceleration is Coulomb's alone
  const double theta = std::atan(slope);
  scene.gravity = 9.81 * Vec3(std::sin(theta), 0.0, -std::cos(theta));
  const Grid grid = Grid::make(16, 16, 1.0);
  // The floor just below the cloth, within the barrier's range.
  const double floor = -(scene.contact.thickness + 0.8 * scene.contact.range_fraction * grid.spacing);
  scene.obstacles = parse_obstacles("plane point=0,0," + std::to_string(floor) + " normal=0,0,1 friction=0.5");
  const RolloutResult r = newton_rollout(scene);
  // From 0.2 s (the cloth settled on the floor) to 1.2 s.
  double moved = 0.0;
  for (int v = 0; v < grid.vertex_count(); ++v) moved += position(r, 72, v).x() - position(r, 12, v).x();
  return moved / grid.vertex_count();
}

TEST(ContactScenes, FrictionHoldsBelowTheCoulombThresholdAndSlidesAbove) {
  const double stuck = slide_on_incline(0.3);  // tan(theta) < mu
  const double sliding = slide_on_incline(0.7);  // tan(theta) > mu
  // Sticking, the mollifier's spring holds the load mu lambda f1(y) = m g sin(theta) at a slip
  // y = eps tan(theta)/(2 mu) per step: a creep of eps_v tan(theta)/(2 mu) per second.
  const double creep = ContactParams{}.friction_velocity * 0.3 / (2.0 * 0.5);
  EXPECT_LT(std::abs(stuck), 2.0 * creep * 1.0);
  RecordProperty("stuck_m", std::to_string(stuck));
  RecordProperty("sliding_m", std::to_string(sliding));
  // Sliding accelerates at g (sin(theta) - mu cos(theta)): about 0.8 m in one second.
  const double theta = std::atan(0.7);
  const double expected = 0.5 * 9.81 * (std::sin(theta) - 0.5 * std::cos(theta)) * (1.2 * 1.2 - 0.2 * 0.2);
  EXPECT_GT(sliding, 0.5 * expected);
  EXPECT_LT(sliding, 1.5 * expected);
}

// A moving obstacle's friction acts on the slip relative to it: a cloth lying on a platform that
// slides 0.2 m sideways (at most 1 m/s^2, well below mu g) rides along with it; on a frictionless
// platform it stays where it was.
double ride_on_platform(double mu, const std::string& file) {
  {
    std::ofstream path(file);
    path << "t,x,y,z\n";
    for (int k = 0; k <= 50; ++k) {
      const double t = 0.2 + k * 0.02;  // 0.2 s to 1.2 s
      path << t << "," << 0.1 * (1.0 - std::cos(std::acos(-1.0) * (t - 0.2))) << ",0,-0.3\n";
    }
  }
  Scene scene = released_scene(84);
  scene.material.damping = 0.0;
  const Grid grid = Grid::make(16, 16, 1.0);
  const double top = -(scene.contact.thickness + 0.8 * scene.contact.range_fraction * grid.spacing);
  // The path holds the box's centre; its first row is where the box starts.
  scene.obstacles = parse_obstacles("box center=0,0,-0.3 size=2,2," + std::to_string(2.0 * (top + 0.3)) +
                                    " rounding=0.01 friction=" + std::to_string(mu) + " path=" + file);
  const RolloutResult r = newton_rollout(scene);
  double moved = 0.0;
  for (int v = 0; v < grid.vertex_count(); ++v) moved += position(r, 84, v).x() - position(r, 0, v).x();
  return moved / grid.vertex_count();
}

TEST(ContactScenes, FrictionCarriesAClothOnAMovingPlatform) {
  const std::string file = ::testing::TempDir() + "sliding_platform.csv";
  EXPECT_NEAR(ride_on_platform(0.5, file), 0.2, 0.01);
  EXPECT_NEAR(ride_on_platform(0.0, file), 0.0, 0.01);
  std::remove(file.c_str());
}

}  // namespace
}  // namespace fnopt
