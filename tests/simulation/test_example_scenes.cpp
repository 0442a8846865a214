// The contact scenes shipped in examples/scenes (docs/design.md §14) load,
// and run on a small grid with pqn and Newton without a vertex coming within the contact thickness
// of an obstacle; each does what its comment says (the table's overhang hangs, the tilted plane's
// cloth slides, the pushed sphere pushes).
#include <gtest/gtest.h>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/baselines/pqn.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {
namespace {

Scene example(const std::string& name) {
  Scene scene = load_scene_file(std::string(FNOPT_SOURCE_DIR) + "/examples/scenes/" + name + ".scene");
  scene.rows = scene.cols = 12;
  return scene;
}

// The rollout's positions with `optimizer`; fails the test where a vertex comes within the thickness.
RolloutResult run_outside(const Scene& scene, InnerOptimizer& optimizer, const std::string& what) {
  RolloutOptions options;
  options.solve = {10, 0.0};
  const RolloutResult rollout = run_rollout(resolve(scene), optimizer, options);
  EXPECT_FALSE(rollout.diverged) << what;
  EXPECT_GT(min_obstacle_distance(scene, rollout.positions), scene.contact.thickness) << what;
  return rollout;
}

TEST(ExampleScenes, EveryContactSceneStaysOutsideItsObstaclesWithPqnAndNewton) {
  for (const char* name : {"drape", "table", "pushed-sphere", "tilted-plane"}) {
    const Scene scene = example(name);
    ASSERT_FALSE(scene.obstacles.empty()) << name;
    PqnOptimizer pqn;
    NewtonOptimizer newton;
    run_outside(scene, pqn, std::string(name) + ", pqn");
    run_outside(scene, newton, std::string(name) + ", newton");
  }
}

TEST(ExampleScenes, EachDoesWhatItsCommentSays) {
  PqnOptimizer pqn;
  // The table top is at z = -0.1 and its edge at x = -0.15: the overhang hangs below the top.
  const RolloutResult table = run_outside(example("table"), pqn, "table");
  const auto last_table = table.positions.back().reshaped(3, table.positions.back().size() / 3);
  EXPECT_LT(last_table.row(2).minCoeff(), -0.3f);
  // tan 30 degrees > mu = 0.4: the cloth slides down the plane (towards +x), far beyond where it fell.
  const RolloutResult tilted = run_outside(example("tilted-plane"), pqn, "tilted-plane");
  const auto first = tilted.positions.front().reshaped(3, tilted.positions.front().size() / 3);
  const auto last = tilted.positions.back().reshaped(3, tilted.positions.back().size() / 3);
  EXPECT_GT(last.row(0).mean() - first.row(0).mean(), 0.3f);
  // The sphere ends at y = 0.4: the cloth, hanging at y = 0, is pushed forward.
  const RolloutResult pushed = run_outside(example("pushed-sphere"), pqn, "pushed-sphere");
  const auto pushed_last = pushed.positions.back().reshaped(3, pushed.positions.back().size() / 3);
  EXPECT_GT(pushed_last.row(1).maxCoeff(), 0.3f);
}

}  // namespace
}  // namespace fnopt
