// Loading a rollout for the viewer: an fnopt rollout's arrays against the file read
// independently (simulation/rollout_file.hpp, io/hdf5_file.hpp), an ARCSim-layout file without per-step
// data, and bad files as one-line errors naming the file.
#include <gtest/gtest.h>

#include <fstream>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/strain.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/viewer/rollout_view.hpp>
#include "tests/util/temp_dir.hpp"
#include "tests/viewer/viewer_fixture.hpp"

namespace fnopt {
namespace {

TEST(ViewerRolloutView, HoldsTheFilesFramesFacesHandlesAndSeries) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "r.h5").string();
  testing::write_test_rollout(path, 6, 9, 12);
  const RolloutView view = load_rollout_view(path);
  const TrajectoryFrames frames = read_trajectory_frames(path);
  const Hdf5File file(path, Hdf5File::Mode::Read);

  EXPECT_EQ(view.kind, "fnopt rollout");
  ASSERT_EQ(view.rows, 6);
  ASSERT_EQ(view.cols, 9);
  ASSERT_EQ(view.frames(), 13);
  EXPECT_EQ(view.times, frames.times);
  for (int t = 0; t < 13; ++t)
    for (int k = 0; k < 3 * 54; ++k) ASSERT_EQ(view.positions[t * 3 * 54 + k], frames.positions[t](k));
  EXPECT_EQ(view.faces, file.read_ints("faces"));
  EXPECT_EQ(view.handle_count, 2);
  EXPECT_EQ(view.handle_positions, file.read_floats("handle_positions"));
  ASSERT_EQ(view.series.size(), 4u);
  for (const auto& [name, values] : view.series) EXPECT_EQ(values, file.read_doubles(name)) << name;

  // A frame's largest vertex strain is the step's recorded max edge strain.
  const std::vector<double> step_max_strain = file.read_doubles("step_max_strain");
  const Grid grid = Grid::make(6, 9, 1.0);
  for (int t = 1; t < 13; ++t) {
    const float largest = *std::max_element(view.strain.begin() + t * 54, view.strain.begin() + (t + 1) * 54);
    EXPECT_NEAR(largest, step_max_strain[t - 1], 1e-5) << "frame " << t;
    EXPECT_NEAR(largest, max_edge_strain(grid, frames.positions[t].cast<double>()), 1e-5) << "frame " << t;
  }
  EXPECT_TRUE(view.distance.empty());
  EXPECT_NE(rollout_metadata_json(view).find("\"reference\":null"), std::string::npos);
}

// The scene's obstacles, each posed at every frame's time: a sphere that follows a CSV path and a
// static plane, with their shapes' numbers as the scene gives them.
TEST(ViewerRolloutView, CarriesTheScenesObstaclesPosedAtEveryFrame) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "r.h5").string(), csv = (dir.path() / "path.csv").string();
  std::ofstream(csv) << "t,x,y,z\n0,0.5,-1,-1\n1,0.5,-0.5,-1\n";
  Scene scene;
  scene.rows = scene.cols = 6;
  scene.frames = 4;
  apply_scene_setting(scene, "obstacle", "sphere center=0.5,-1,-1 radius=0.2 path=" + csv +
                                             ";plane point=0,0,-3 normal=0,0,2");
  PqnOptimizer pqn;
  const RolloutResult rollout = run_rollout(resolve(scene), pqn, {});
  write_rollout_file(path, rollout, to_scene_text(scene), pqn.settings());
  const RolloutView view = load_rollout_view(path);
  ASSERT_EQ(view.obstacles.size(), 2u);
  const ObstacleView& sphere = view.obstacles[0];
  EXPECT_EQ(sphere.shape, "sphere");
  EXPECT_EQ(sphere.point, (std::vector<double>{0.5, -1.0, -1.0}));
  EXPECT_EQ(sphere.radius, 0.2);
  ASSERT_EQ(sphere.offsets.size(), 3u * view.frames());
  for (int f = 0; f < view.frames(); ++f) {  // the path moves 0.5 m along y in 1 s
    EXPECT_FLOAT_EQ(sphere.offsets[3 * f + 1], static_cast<float>(0.5 * view.times[f])) << f;
    EXPECT_EQ(sphere.offsets[3 * f], 0.0f);
  }
  EXPECT_EQ(view.obstacles[1].shape, "plane");
  EXPECT_EQ(view.obstacles[1].axis, (std::vector<double>{0.0, 0.0, 1.0}));  // the unit normal
  const std::string meta = rollout_metadata_json(view);
  EXPECT_NE(meta.find("\"obstacles\":[{\"shape\":\"sphere\""), std::string::npos) << meta;
  testing::write_test_rollout(path, 6, 6, 2);
  EXPECT_NE(rollout_metadata_json(load_rollout_view(path)).find("\"obstacles\":[]"), std::string::npos);
}

// A mesh obstacle's triangles once; its vertices once for a static mesh and at every frame for an
// animated one, each frame's vertices translated by the frame's offset being the mesh posed at
// the frame's time (Obstacle::mesh_vertices); the JSON gives the sizes only.
TEST(ViewerRolloutView, CarriesMeshObstaclesTrianglesOnceAndAnAnimatedOnesVerticesPerFrame) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "r.h5").string();
  const Scene scene = testing::write_mesh_obstacle_rollout(dir.path(), path, 4);
  const RolloutView view = load_rollout_view(path);
  const int T = view.frames();
  ASSERT_EQ(view.obstacles.size(), 3u);
  for (int k = 0; k < 2; ++k) {
    const ObstacleView& o = view.obstacles[k];
    EXPECT_EQ(o.shape, "mesh");
    EXPECT_EQ(o.triangles, (std::vector<int>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3})) << k;
    ASSERT_EQ(o.vertex_count, 4);
    ASSERT_EQ(o.vertex_frames(), k == 0 ? 1 : T) << "a static mesh's vertices are sent once";
    ASSERT_EQ(o.offsets.size(), 3u * T);
    std::vector<Vec3> posed;
    for (int f = 0; f < T; ++f) {
      scene.obstacles[k].mesh_vertices(view.times[f], posed);
      const float* frame = o.vertices.data() + (k == 0 ? 0 : 12 * f);
      for (int v = 0; v < 4; ++v)
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(frame[3 * v + c] + o.offsets[3 * f + c], posed[v][c], 1e-6) << k << " " << f << " " << v;
    }
  }
  const std::vector<float>& walk = view.obstacles[1].vertices;
  EXPECT_GT(walk[12 * (T - 1)] - walk[0], 0.1f) << "the animated mesh walks along x";
  EXPECT_GT(view.obstacles[1].offsets[3 * T - 1], 0.0f) << "and its path lifts it";
  EXPECT_TRUE(view.obstacles[2].triangles.empty());
  const std::string meta = rollout_metadata_json(view);
  EXPECT_NE(meta.find("\"triangle_count\":4,\"vertex_count\":4,\"vertex_frames\":1}"), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"vertex_frames\":" + std::to_string(T) + "}"), std::string::npos) << meta;
  EXPECT_EQ(meta.find("vertices\":["), std::string::npos) << "the arrays are endpoints of their own";
}

TEST(ViewerRolloutView, ReadsAnArcsimLayoutFileWithoutSeries) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "arcsim.h5").string();
  const Grid grid = Grid::make(4, 4, 1.0);
  {
    Hdf5File file(path, Hdf5File::Mode::Create);
    const Eigen::VectorXf rest = grid.rest_positions().cast<float>();
    std::vector<float> positions;
    for (int t = 0; t < 3; ++t) positions.insert(positions.end(), rest.data(), rest.data() + rest.size());
    file.write("positions", {3, 4, 4, 3}, positions.data());
    const std::vector<double> times = {0.0, 1.0 / 30, 2.0 / 30};
    file.write("times_s", {3}, times.data());
    const auto faces = grid.triangles();
    file.write("faces", {18, 3}, faces.data());
    const std::vector<float> handles = {0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0};
    file.write("handle_positions", {3, 2, 3}, handles.data());
  }
  const RolloutView view = load_rollout_view(path);
  EXPECT_EQ(view.kind, "ARCSim-layout file");
  EXPECT_EQ(view.frames(), 3);
  EXPECT_EQ(view.handle_count, 2);
  EXPECT_TRUE(view.series.empty());
  for (const float s : view.strain) EXPECT_NEAR(s, 0.0f, 1e-6);
  EXPECT_NE(rollout_metadata_json(view).find("\"series\":{}"), std::string::npos);
}

// The error's one line, "" if there was none.
std::string load_error(const std::string& path, const std::string& reference = "") {
  try {
    load_rollout_view(path, reference);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ViewerRolloutView, BadFilesAreOneLineErrorsNamingTheFile) {
  const testing::TempDir dir;
  const std::string good = (dir.path() / "r.h5").string();
  testing::write_test_rollout(good, 4, 4, 3);
  const std::string text = dir.write("notes.h5", "not an HDF5 file\n");
  const std::string no_positions = (dir.path() / "empty.h5").string();
  {
    Hdf5File file(no_positions, Hdf5File::Mode::Create);
    const double t = 0.0;
    file.write("times_s", {1}, &t);
  }
  const std::string missing = (dir.path() / "missing.h5").string();
  for (const auto& [path, reference, says] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{missing, "", "no such file"},
                                                                      {text, "", ""},
                                                                      {no_positions, "", "positions"},
                                                                      {good, missing, "no such file"},
                                                                      {dir.path().string(), "", "not a file"}}) {
    const std::string error = load_error(path, reference);
    const std::string named = reference.empty() ? path : reference;
    ASSERT_FALSE(error.empty()) << path;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_NE(error.find(named), std::string::npos) << error;
    EXPECT_NE(error.find(says), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace fnopt
