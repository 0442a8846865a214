// HDF5 rollout files: write -> read round trip, the ARCSim layout, atomic writes, bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/contact/obstacle_spec.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/io/obj_file.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("fnopt_test_io_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

RolloutResult small_rollout() {
  RolloutResult r;
  r.grid = Grid::make(3, 4, 1.0);
  r.handle_vertices = {0, 3};
  r.dt = 0.01;
  for (int t = 0; t < 3; ++t) {
    r.times.push_back(t * r.dt);
    Eigen::VectorXf x = r.grid.rest_positions().cast<float>();
    x.array() += 0.25f * t;
    r.positions.push_back(x);
    r.handle_targets.push_back({Vec3(t, 0, 0), Vec3(1, t, 0)});
    if (t > 0) {
      StepRecord s;
      s.wall_ms = 1.5 * t;
      s.iterations = t;
      s.status = SolveStatus::Converged;
      r.steps.push_back(s);
    }
  }
  return r;
}

TEST(RolloutFile, WriteReadRoundTrip) {
  const auto dir = temp_dir("roundtrip");
  const std::string path = (dir / "r.h5").string();
  const RolloutResult r = small_rollout();
  write_rollout_file(path, r, "res = 3\n", "newton: test");
  const TrajectoryFrames frames = read_trajectory_frames(path);
  EXPECT_EQ(frames.rows, 3);
  EXPECT_EQ(frames.cols, 4);
  ASSERT_EQ(frames.positions.size(), 3u);
  for (int t = 0; t < 3; ++t) {
    EXPECT_EQ(frames.positions[t], r.positions[t]);
    EXPECT_DOUBLE_EQ(frames.times[t], r.times[t]);
  }
  const Hdf5File file(path, Hdf5File::Mode::Read);
  EXPECT_EQ(file.string_attribute("scene"), "res = 3\n");
  EXPECT_EQ(file.string_attribute("optimizer"), "newton: test");
  EXPECT_EQ(file.dims("faces"), (std::vector<hsize_t>{12, 3}));
  EXPECT_EQ(file.dims("handle_positions"), (std::vector<hsize_t>{3, 2, 3}));
  EXPECT_EQ(file.read_ints("step_iterations"), (std::vector<int>{1, 2}));
  EXPECT_EQ(file.read_floats("handle_positions")[16], 2.0f);  // frame 2, handle 1, y
  // Only the final file is left: the temporary name was renamed.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator{}), 1);
}

// The rest positions a file stores are the cloth as its scene placed it: horizontal for a
// horizontal placement (the grid's own rest pose is vertical).
TEST(RolloutFile, StoresTheScenesRestPlacement) {
  const auto dir = temp_dir("placement");
  const std::string path = (dir / "r.h5").string();
  Scene scene;
  scene.rows = scene.cols = 4;
  scene.frames = 2;
  scene.handles = "none";
  scene.placement = Placement::Horizontal;
  PqnOptimizer pqn;
  const RolloutResult r = run_rollout(resolve(scene), pqn, RolloutOptions{}, {});
  write_rollout_file(path, r, to_scene_text(scene), "pqn");
  const std::vector<float> rest = Hdf5File(path, Hdf5File::Mode::Read).read_floats("rest_positions");
  ASSERT_EQ(rest.size(), 48u);
  for (int v = 0; v < 16; ++v) EXPECT_EQ(rest[3 * v + 2], 0.0f) << "vertex " << v;  // z = 0: in the x-y plane
  EXPECT_EQ(Eigen::Map<const Eigen::VectorXf>(rest.data(), 48), r.positions.front());
}

// A rollout stopped by a divergence: the step that diverged kept no frame, so the per-step
// datasets end with the last kept frame (finite everywhere) and the attributes say why.
TEST(RolloutFile, ADivergedRolloutStoresNoNaNAndSaysWhereItStopped) {
  const auto dir = temp_dir("diverged");
  const std::string path = (dir / "r.h5").string();
  RolloutResult r = small_rollout();
  StepRecord blown;
  blown.status = SolveStatus::NonFinite;
  blown.loss = blown.energy = NAN;
  blown.max_strain = INFINITY;
  r.steps.push_back(blown);
  r.diverged = true;
  r.divergence = "diverged at step 3 (t = 0.03 s): non-finite state";
  write_rollout_file(path, r, "res = 3\n", "pqn: test");
  const Hdf5File file(path, Hdf5File::Mode::Read);
  for (const char* name : {"step_loss", "step_energy", "step_max_strain", "step_wall_ms"}) {
    const std::vector<double> values = file.read_doubles(name);
    ASSERT_EQ(values.size(), 2u) << name;
    for (double v : values) EXPECT_TRUE(std::isfinite(v)) << name;
  }
  EXPECT_EQ(file.int_attribute("rows"), 3);
  EXPECT_EQ(file.int_attribute("diverged"), 1);
  EXPECT_EQ(file.int_attribute("diverged_step"), 3);
  EXPECT_EQ(file.string_attribute("divergence"), r.divergence);
  EXPECT_EQ(file.string_attribute("unit", "positions"), "m");
  EXPECT_EQ(file.string_attribute("unit", "step_max_strain").rfind("fraction", 0), 0u);
  EXPECT_NE(file.string_attribute("legend", "step_status").find("4 non-finite"), std::string::npos);
}

// A tetrahedron as an OBJ file's text, its vertices moved by `shift`.
std::string tetrahedron_obj(double shift) {
  std::string text;
  for (const Vec3& v : {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)})
    text += "v " + std::to_string(v.x() + shift) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
  return text + "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
}

void expect_same_mesh(const Obstacle& read, const Obstacle& written) {
  ASSERT_TRUE(read.is_mesh());
  EXPECT_EQ(read.mesh_source(), written.mesh_source());
  EXPECT_EQ(read.to_text(), written.to_text());
  EXPECT_EQ(read.mesh()->triangles(), written.mesh()->triangles());
  ASSERT_EQ(read.mesh()->frame_count(), written.mesh()->frame_count());
  for (int k = 0; k < written.mesh()->frame_count(); ++k) EXPECT_EQ(read.mesh()->frame(k), written.mesh()->frame(k));
}

// A rollout keeps its meshes: with the OBJ file and the sequence's files deleted, its scene still
// reads, with the same meshes, named by their places among the obstacles.
TEST(RolloutFile, StoresItsMeshObstaclesSoThatTheSceneReadsWithoutTheirFiles) {
  const auto dir = temp_dir("meshes");
  std::ofstream(dir / "tet.obj") << tetrahedron_obj(0.0);
  for (int k = 0; k < 3; ++k) std::ofstream(dir / ("seq000" + std::to_string(k) + ".obj")) << tetrahedron_obj(0.1 * k);
  Scene scene;
  scene.rows = scene.cols = 3;
  scene.obstacles = parse_obstacles("plane point=0,0,-5 normal=0,0,1; mesh file=" + (dir / "tet.obj").string() +
                                    " scale=0.5 offset=3,0,0; mesh sequence=" + (dir / "seq").string() +
                                    " fps=30 offset=-3,0,0 friction=0.2");
  const std::string path = (dir / "r.h5").string();
  write_rollout_file(path, small_rollout(), scene, "pqn: test");
  for (const char* name : {"tet.obj", "seq0000.obj", "seq0001.obj", "seq0002.obj"}) std::filesystem::remove(dir / name);

  const Hdf5File file(path, Hdf5File::Mode::Read);
  EXPECT_EQ(file.string_attribute("scene"), to_scene_text(scene));
  EXPECT_FALSE(file.has("mesh_1_vertices"));
  EXPECT_EQ(file.dims("mesh_2_vertices"), (std::vector<hsize_t>{1, 4, 3}));
  EXPECT_EQ(file.dims("mesh_3_vertices"), (std::vector<hsize_t>{3, 4, 3}));
  EXPECT_EQ(file.dims("mesh_3_triangles"), (std::vector<hsize_t>{4, 3}));
  EXPECT_EQ(file.string_attribute("source", "mesh_2_vertices"), (dir / "tet.obj").string());
  EXPECT_EQ(file.read_doubles("mesh_3_vertices")[3 * 4 * 2], 0.2);  // frame 2 as given: shifted, not offset

  const Scene read = read_rollout_scene(path);
  ASSERT_EQ(read.obstacles.size(), 3u);
  expect_same_mesh(read.obstacles[1], scene.obstacles[1]);
  expect_same_mesh(read.obstacles[2], scene.obstacles[2]);
  EXPECT_EQ(to_scene_text(read), to_scene_text(scene));
  // Outside the reading, the files are what counts: they are gone.
  EXPECT_THROW(load_scene_text(to_scene_text(scene), "scene"), Error);
  // A rollout written from the scene's text alone stores no mesh.
  write_rollout_file(path, small_rollout(), to_scene_text(scene), "pqn: test");
  EXPECT_FALSE(Hdf5File(path, Hdf5File::Mode::Read).has("mesh_2_vertices"));
  EXPECT_THROW(read_rollout_scene(path), Error);
}

TEST(RolloutFile, RejectsMissingAndForeignFiles) {
  const auto dir = temp_dir("bad");
  EXPECT_THROW(read_trajectory_frames((dir / "missing.h5").string()), Error);
  const std::string text = (dir / "text.h5").string();
  std::ofstream(text) << "not hdf5";
  try {
    read_trajectory_frames(text);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not an HDF5 file"), std::string::npos) << e.what();
  }
  const std::string empty = (dir / "empty.h5").string();
  { Hdf5File(empty, Hdf5File::Mode::Create); }
  try {
    read_trajectory_frames(empty);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("positions"), std::string::npos) << e.what();
  }
}

TEST(RolloutFile, FailedWriteLeavesNothingBehind) {
  const auto dir = temp_dir("unwritable");
  const std::string path = (dir / "no_such_subdir" / "r.h5").string();
  EXPECT_THROW(write_rollout_file(path, small_rollout(), "", ""), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(ObjFile, WritesVerticesAndOneBasedFaces) {
  const auto dir = temp_dir("obj");
  const Grid grid = Grid::make(3, 3, 1.0);
  write_obj_file((dir / "f.obj").string(), grid, grid.rest_positions().cast<float>());
  std::ifstream in(dir / "f.obj");
  int v = 0, f = 0;
  std::string line, first_face;
  while (std::getline(in, line)) {
    v += line.rfind("v ", 0) == 0;
    if (line.rfind("f ", 0) == 0 && f++ == 0) first_face = line;
  }
  EXPECT_EQ(v, 9);
  EXPECT_EQ(f, 8);
  EXPECT_EQ(first_face, "f 1 2 5");
}

}  // namespace
}  // namespace fnopt
