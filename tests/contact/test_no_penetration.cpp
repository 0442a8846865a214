// No penetration, ever, for every core method: a released horizontal cloth falls on each shape,
// static and moving toward it, at 16x16 for 60 steps; every stored frame keeps every vertex
// outside every obstacle (the distance at each frame, obstacles posed at its time), the cloth
// does reach the obstacle's range, and Newton converges on every step.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>

#include <fnopt/baselines/adam.hpp>
#include <fnopt/baselines/gradient_descent.hpp>
#include <fnopt/baselines/lbfgs.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

struct Method {
  std::string name;
  std::function<std::unique_ptr<InnerOptimizer>()> make;
  InnerSolveOptions solve;
};

std::vector<Method> core_methods() {
  LbfgsParams with_line_search;
  with_line_search.line_search = true;
  return {
      {"newton", [] { return std::make_unique<NewtonOptimizer>(); }, NewtonOptimizer::reference_solve_options()},
      {"pqn", [] { return std::make_unique<PqnOptimizer>(); }, {30}},
      {"lbfgs", [] { return std::make_unique<LbfgsOptimizer>(); }, {30}},
      {"lbfgs-ls", [=] { return std::make_unique<LbfgsOptimizer>(with_line_search); }, {30}},
      {"adam", [] { return std::make_unique<AdamOptimizer>(); }, {30}},
      {"gd", [] { return std::make_unique<GradientDescentOptimizer>(); }, {50}},
  };
}

// The shapes under a cloth released at z = 0: each surface's top at z = -0.1.
std::vector<std::string> shape_specs() {
  return {"plane point=0,0,-0.1 normal=0.1,0.05,1", "sphere center=0.05,0,-0.35 radius=0.25",
          "box center=0,0.02,-0.3 size=0.5,0.6,0.4 rounding=0.03", "capsule a=-0.5,0,-0.25 b=0.5,0.1,-0.25 radius=0.15"};
}

Scene falling_scene(const std::string& obstacle) {
  Scene scene;
  scene.rows = scene.cols = 16;
  scene.frames = 60;
  scene.handles = "none";
  scene.placement = Placement::Horizontal;
  scene.obstacles = parse_obstacles(obstacle);
  return scene;
}

// A path that lifts the obstacle by 0.4 m over the rollout's second half-second.
std::string rising_path(const Obstacle& obstacle, const std::string& file) {
  const Vec3 p = obstacle.point();
  std::ofstream out(file);
  out << "t,x,y,z\n0.5," << p.x() << "," << p.y() << "," << p.z() << "\n1.0," << p.x() << "," << p.y() << ","
      << p.z() + 0.4 << "\n";
  return file;
}

void expect_no_penetration(const Scene& scene, const Method& method, const std::string& what) {
  auto optimizer = method.make();
  RolloutOptions options;
  options.solve = method.solve;
  const RolloutResult r = run_rollout(resolve(scene), *optimizer, options);
  ASSERT_FALSE(r.diverged) << what << ": " << r.divergence;
  ASSERT_EQ(r.positions.size(), 61u) << what;
  for (std::size_t f = 0; f < r.positions.size(); ++f) {
    const double d =
        min_obstacle_distance(scene.obstacles, r.positions[f].cast<double>(), r.grid.rows, r.grid.cols, f * scene.dt);
    ASSERT_GT(d, 0.0) << what << " frame " << f;
  }
  const double dhat = scene.contact.range_fraction * resolve(scene).grid.spacing;
  EXPECT_LT(min_obstacle_distance(scene, r.positions), scene.contact.thickness + dhat) << what << ": no contact";
  if (method.name == "newton") {
    for (std::size_t s = 0; s < r.steps.size(); ++s)
      EXPECT_TRUE(is_converged(r.steps[s].status)) << what << " step " << s + 1 << ": " << to_string(r.steps[s].status);
  }
}

TEST(NoPenetration, EveryMethodOnEveryStaticShape) {
  for (const std::string& spec : shape_specs())
    for (const Method& method : core_methods()) expect_no_penetration(falling_scene(spec), method, method.name + " on " + spec);
}

TEST(NoPenetration, EveryMethodOnEveryMovingShape) {
  const std::string file = ::testing::TempDir() + "rising_obstacle.csv";
  for (const std::string& spec : shape_specs()) {
    const std::string moving = spec + " path=" + rising_path(parse_obstacle(spec), file);
    for (const Method& method : core_methods())
      expect_no_penetration(falling_scene(moving), method, method.name + " on " + moving);
  }
  std::remove(file.c_str());
}

}  // namespace
}  // namespace fnopt
