// fnopt evaluate as a user runs it: a rollout against itself, the per-frame and per-step tables
// it writes, and the per-step table's rows making up the printed mean; the self- and mesh
// intersections of a rollout's own frames.
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>
#include <sstream>
#include <vector>

#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include "run_fnopt.hpp"
#include "tests/util/temp_dir.hpp"

namespace {

TEST(EvaluateCli, WritesThePerFrameAndPerStepTablesBehindItsMeans) {
  const fnopt::testing::TempDir tmp;
  const auto rollout = (tmp.path() / "newton.h5").string();
  ASSERT_EQ(run_fnopt("simulate --optimizer newton --res 8 --frames 12 --threads 1 --out " + rollout).status, 0);

  const auto per_frame = tmp.path() / "frames.csv", per_step = tmp.path() / "steps.csv";
  const CommandResult r = run_fnopt("evaluate --reference " + rollout + " " + rollout +
                                    " --optimizer gd --iters 3 --step-samples 4 --threads 1 --per-frame " +
                                    per_frame.string() + " --per-step " + per_step.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("e_3D x 10^2 = 0.0000"), std::string::npos) << r.output;

  std::string header;
  const auto frames = csv_rows(per_frame, header);
  EXPECT_EQ(header, "t_s,e_cd_x1e3,e_3d_x1e2");
  EXPECT_EQ(frames.size(), 13u);

  const auto steps = csv_rows(per_step, header);
  EXPECT_EQ(header,
            "step,initial_value,newton_value,method_value,step_error,status,newton_negative_eigenvalues,"
            "newton_iterations,newton_cg_products");
  ASSERT_EQ(steps.size(), 4u);
  double sum = 0.0;
  for (const auto& row : steps) {
    ASSERT_EQ(row.size(), 9u);
    const double initial = std::stod(row[1]), newton = std::stod(row[2]), method = std::stod(row[3]);
    const double error = std::stod(row[4]);
    // The error is the remaining fraction of the start's distance to Newton's minimum.
    EXPECT_NEAR(error, (method - newton) / (initial - newton), 1e-5 * std::abs(error) + 1e-9) << row[0];
    EXPECT_GT(error, 0.0) << "three gradient steps do not reach the minimum, step " << row[0];
    EXPECT_EQ(row[5], "iteration-budget");
    EXPECT_EQ(row[6], "0") << "the hanging cloth's step ends at a minimum, step " << row[0];
    // Newton took at least one iteration, each with at least one product with H.
    EXPECT_GE(std::stoi(row[7]), 1) << row[0];
    EXPECT_GE(std::stol(row[8]), std::stol(row[7])) << row[0];
    sum += error;
  }
  char mean[32];
  std::snprintf(mean, sizeof mean, "mean %.4g", sum / 4.0);
  EXPECT_NE(r.output.find(mean), std::string::npos) << mean << "\n" << r.output;
  EXPECT_NE(r.output.find("per-step errors: " + per_step.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Newton's step ends at a saddle of L (negative eigenvalues of the exact Hessian) on 0 of "
                          "the 4 states; the method ends below it (error < -1e-6) on 0"),
            std::string::npos)
      << r.output;
}

TEST(EvaluateCli, PerStepNeedsAnOptimizer) {
  const fnopt::testing::TempDir tmp;
  const auto rollout = (tmp.path() / "newton.h5").string();
  ASSERT_EQ(run_fnopt("simulate --optimizer newton --res 8 --frames 2 --threads 1 --out " + rollout).status, 0);
  const CommandResult r =
      run_fnopt("evaluate --reference " + rollout + " " + rollout + " --per-step " + (tmp.path() / "s.csv").string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--per-step requires --optimizer"), std::string::npos) << r.output;
}

// A rollout that diverged: evaluate says so, and where its numbers come from.
TEST(EvaluateCli, SaysThatARolloutDivergedAndWhatItsNumbersCover) {
  const fnopt::testing::TempDir tmp;
  const auto rollout = (tmp.path() / "adam.h5").string();
  const CommandResult sim =
      run_fnopt("simulate --optimizer adam --lr 1000 --res 8 --frames 6 --threads 1 --out " + rollout);
  ASSERT_EQ(sim.status, 2) << sim.output;  // simulate reports the divergence as its error
  EXPECT_NE(sim.output.find("edge strain"), std::string::npos) << sim.output;
  EXPECT_NE(sim.output.find("% above the limit 300 %"), std::string::npos) << sim.output;
  const CommandResult r = run_fnopt("evaluate --no-chamfer --reference " + rollout + " " + rollout);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("diverged:  diverged at step 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("max edge strain of the rollout's frames"), std::string::npos) << r.output;
}

// A two-frame 4 x 4 trajectory in the ARCSim layout: flat, then with the edge (3,2)-(3,3) stood
// up through the first quad (a crossing no simulation made, for the count to find).
std::string write_pierced_cloth(const fnopt::testing::TempDir& tmp) {
  const std::string path = (tmp.path() / "pierced.h5").string();
  std::vector<float> positions;
  for (int frame = 0; frame < 2; ++frame)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        float x = j, y = -i, z = 0.0f;
        if (frame == 1 && i == 3 && j >= 2) x = 0.3f, y = -0.4f, z = j == 2 ? 1.0f : -1.0f;
        positions.insert(positions.end(), {x, y, z});
      }
  const std::vector<double> times = {0.0, 0.1};
  fnopt::Hdf5File file(path, fnopt::Hdf5File::Mode::Create);
  file.write("positions", {2, 4, 4, 3}, positions.data());
  file.write("times_s", {2}, times.data());
  return path;
}

TEST(EvaluateCli, WithoutAReferenceItCountsTheRolloutsOwnSelfIntersections) {
  const fnopt::testing::TempDir tmp;
  const CommandResult pierced = run_fnopt("evaluate " + write_pierced_cloth(tmp));
  ASSERT_EQ(pierced.status, 0) << pierced.output;
  EXPECT_EQ(pierced.output.find("e_CD"), std::string::npos) << pierced.output;
  EXPECT_NE(pierced.output.find("max edge strain"), std::string::npos) << pierced.output;
  const auto at = pierced.output.find("self-intersections = ");
  ASSERT_NE(at, std::string::npos) << pierced.output;
  EXPECT_GT(std::stol(pierced.output.substr(at + 21)), 0) << pierced.output;
  EXPECT_NE(pierced.output.find("; 1 frames with any"), std::string::npos) << pierced.output;

  const auto rollout = (tmp.path() / "newton.h5").string();
  ASSERT_EQ(run_fnopt("simulate --optimizer newton --res 8 --frames 4 --threads 1 --out " + rollout).status, 0);
  const CommandResult hanging = run_fnopt("evaluate " + rollout);
  ASSERT_EQ(hanging.status, 0) << hanging.output;
  EXPECT_NE(hanging.output.find("self-intersections = 0 "), std::string::npos) << hanging.output;
  EXPECT_EQ(hanging.output.find("mesh intersections"), std::string::npos) << "no mesh obstacle: " << hanging.output;
  // The hanging cloth stays about flat: its closest vertex-disjoint pairs about h/sqrt(2) apart; no
  // self-contact, so no range to count frames in.
  const auto cloth = hanging.output.find("min cloth distance = ");
  ASSERT_NE(cloth, std::string::npos) << hanging.output;
  EXPECT_NEAR(std::stod(hanging.output.substr(cloth + 21)), 1.0 / 7.0 / std::sqrt(2.0), 0.01) << hanging.output;
  EXPECT_EQ(hanging.output.find("frames with a pair within"), std::string::npos) << hanging.output;
  // Released, self-contact is on: the frames within its range are counted (none for a flat fall).
  const auto released = (tmp.path() / "released.h5").string();
  ASSERT_EQ(run_fnopt("simulate --res 8 --frames 4 --handles none --threads 1 --out " + released).status, 0);
  const CommandResult falling = run_fnopt("evaluate " + released);
  EXPECT_NE(falling.output.find("; 0 frames with a pair within self-contact's thickness + range, 0.0025 m)"),
            std::string::npos)
      << falling.output;
  // The per-frame errors and the per-step error need a reference.
  EXPECT_EQ(run_fnopt("evaluate " + rollout + " --per-frame " + (tmp.path() / "f.csv").string()).status, 2);
  EXPECT_EQ(run_fnopt("evaluate " + rollout + " --optimizer pqn").status, 2);
}

// A 4 x 4 cloth lying flat, then lifted through a mesh spike (one triangle standing over it in
// the plane y = 0.08): each of the spike's two slanted edges passes through one cloth triangle.
// evaluate counts them from the mesh the rollout stores, its OBJ file deleted.
TEST(EvaluateCli, CountsTheCrossingsOfTheClothAndAMeshObstacleFromTheMeshTheRolloutStores) {
  const fnopt::testing::TempDir tmp;
  const std::string obj = tmp.write("spike.obj", "v -0.1 0.08 0.5\nv 0.1 0.08 0.5\nv 0 0.08 1.5\nf 1 2 3\n");
  fnopt::Scene scene;
  scene.rows = scene.cols = 4;
  scene.handles = "none";
  scene.placement = fnopt::Placement::Horizontal;
  scene.obstacles = fnopt::parse_obstacles("mesh file=" + obj);
  fnopt::RolloutResult rollout;
  rollout.grid = fnopt::Grid::make(4, 4, 1.0);
  rollout.dt = scene.dt;
  const Eigen::VectorXf flat = fnopt::placed_rest_positions(rollout.grid, scene.placement).cast<float>();
  rollout.positions = {flat, flat + Eigen::Vector3f(0, 0, 1).replicate(16, 1)};
  rollout.times = {0.0, scene.dt};
  rollout.handle_targets.resize(2);
  rollout.steps.resize(1);
  const std::string path = (tmp.path() / "spike.h5").string();
  fnopt::write_rollout_file(path, rollout, scene, "by hand");
  std::filesystem::remove(obj);

  const CommandResult r = run_fnopt("evaluate " + path);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("self-intersections = 0 "), std::string::npos) << r.output;
  const auto at = r.output.find("mesh intersections = 2 ");
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("summed over 2 frames and 1 mesh obstacle; 1 frames with any)", at), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("min obstacle distance = "), std::string::npos) << r.output;
}

// The drop of fnopt's example mesh sphere: simulate prints its closest approach, and evaluate
// the same from the file, with no crossing of the mesh.
TEST(EvaluateCli, AClothDroppedOnAMeshHasNoMeshIntersections) {
  const fnopt::testing::TempDir tmp;
  const std::string scene = tmp.write(
      "drop.scene", "handles = none\nplacement = horizontal\nobstacle = mesh file=" + std::string(FNOPT_SOURCE_DIR) +
                        "/examples/meshes/sphere.obj friction=0.3\n"
                        "obstacle = plane point=0,0,-0.6 normal=0,0,1\n");
  const auto rollout = (tmp.path() / "drop.h5").string();
  const CommandResult sim =
      run_fnopt("simulate --scene " + scene + " --res 8 --frames 20 --threads 1 --out " + rollout);
  ASSERT_EQ(sim.status, 0) << sim.output;
  const std::string key = "min obstacle distance = ";
  ASSERT_NE(sim.output.find(key), std::string::npos) << sim.output;
  const double simulated = std::stod(sim.output.substr(sim.output.find(key) + key.size()));
  EXPECT_GT(simulated, 0.0) << sim.output;
  const CommandResult r = run_fnopt("evaluate " + rollout + " --threads 1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NEAR(std::stod(r.output.substr(r.output.find(key) + key.size())), simulated, 1e-6) << r.output;
  EXPECT_NE(r.output.find("mesh intersections = 0 "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0 frames with any)", r.output.find("mesh intersections")), std::string::npos) << r.output;
}

}  // namespace
