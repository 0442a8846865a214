// The viewer's server, started in-process on an ephemeral port and queried with httplib's
// client: the data endpoints against the files read independently (simulation/rollout_file.hpp), a
// compare directory's kept rollouts and references, 404 for everything off the whitelist
// (path traversal included), and one-line errors before serving.
#include <gtest/gtest.h>

#include <filesystem>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/viewer/rollout_view.hpp>
#include "tests/util/temp_dir.hpp"
#include "tests/viewer/viewer_fixture.hpp"
// Last: httplib pulls in <resolv.h>, whose macro _res breaks Eigen's headers.
#include <httplib.h>

namespace fnopt {
namespace {

using testing::json_numbers;
using testing::values_of;

// GET `path`; the body, or a failed expectation and "".
std::string get(httplib::Client& client, const std::string& path, const std::string& content_type) {
  const auto response = client.Get(path.c_str());
  if (!response) {
    ADD_FAILURE() << path << ": no response";
    return "";
  }
  EXPECT_EQ(response->status, 200) << path;
  EXPECT_EQ(response->get_header_value("Content-Type").rfind(content_type, 0), 0u) << path;
  return response->body;
}

// Per vertex, the largest |e|/L - 1 over its grid edges, written out here independently.
std::vector<float> strain_of(const TrajectoryFrames& frames, const Eigen::VectorXf& rest) {
  const int R = frames.rows, C = frames.cols;
  std::vector<float> strain;
  for (const auto& x : frames.positions)
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) {
        float largest = -1.0f;
        for (const auto& [di, dj] : {std::pair{0, 1}, {0, -1}, {1, 0}, {-1, 0}}) {
          const int a = i * C + j, b = (i + di) * C + (j + dj);
          if (i + di < 0 || i + di >= R || j + dj < 0 || j + dj >= C) continue;
          largest = std::max(largest, (x.segment<3>(3 * a) - x.segment<3>(3 * b)).norm() /
                                              (rest.segment<3>(3 * a) - rest.segment<3>(3 * b)).norm() -
                                          1.0f);
        }
        strain.push_back(largest);
      }
  return strain;
}

class ViewerServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fnopt::testing::TempDir();
    rollout_ = (dir_->path() / "rollout.h5").string();
    reference_ = (dir_->path() / "reference.h5").string();
    testing::write_test_rollout(rollout_, 7, 10, 15);
    testing::write_test_rollout(reference_, 7, 10, 15, "rot_h0");
  }
  static void TearDownTestSuite() { delete dir_; }
  static fnopt::testing::TempDir* dir_;
  static std::string rollout_, reference_;
};

fnopt::testing::TempDir* ViewerServerTest::dir_ = nullptr;
std::string ViewerServerTest::rollout_, ViewerServerTest::reference_;

TEST_F(ViewerServerTest, DataEndpointsMatchTheFile) {
  testing::RunningViewer viewer({rollout_, reference_});
  httplib::Client client("127.0.0.1", viewer.port());
  const TrajectoryFrames frames = read_trajectory_frames(rollout_);
  const TrajectoryFrames reference = read_trajectory_frames(reference_);
  const Hdf5File file(rollout_, Hdf5File::Mode::Read);
  const int T = 16, N = 70;
  ASSERT_EQ(static_cast<int>(frames.positions.size()), T);

  EXPECT_EQ(get(client, "/api/session", "application/json"), "{\"mode\":\"rollout\",\"rollout\":0}");
  const std::string meta = get(client, "/api/rollouts/0/meta", "application/json");
  EXPECT_NE(meta.find("\"rows\":7,\"cols\":10,\"frames\":16"), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"reference\":\"reference.h5\""), std::string::npos);
  EXPECT_EQ(json_numbers(meta, "times"), frames.times);
  for (const char* name : {"step_max_strain", "step_energy", "step_iterations", "step_wall_ms"}) {
    const std::vector<double> series = json_numbers(meta, name), stored = file.read_doubles(name);
    ASSERT_EQ(series.size(), stored.size()) << name;
    for (std::size_t k = 0; k < stored.size(); ++k) EXPECT_DOUBLE_EQ(series[k], stored[k]) << name << " " << k;
  }
  const std::vector<double> handles = json_numbers(meta, "handle_positions");
  const std::vector<float> stored_handles = file.read_floats("handle_positions");
  ASSERT_EQ(handles.size(), stored_handles.size());
  for (std::size_t k = 0; k < handles.size(); ++k) EXPECT_EQ(static_cast<float>(handles[k]), stored_handles[k]);

  const auto positions = values_of<float>(get(client, "/api/rollouts/0/positions", "application/octet-stream"));
  ASSERT_EQ(positions.size(), static_cast<std::size_t>(T * N * 3));
  for (int t = 0; t < T; ++t)
    for (int k = 0; k < 3 * N; ++k) ASSERT_EQ(positions[t * 3 * N + k], frames.positions[t](k));
  EXPECT_EQ(values_of<int>(get(client, "/api/rollouts/0/faces", "application/octet-stream")), file.read_ints("faces"));

  const std::vector<float> rest = file.read_floats("rest_positions");
  const std::vector<float> expected_strain = strain_of(frames, Eigen::Map<const Eigen::VectorXf>(rest.data(), 3 * N));
  const auto strain = values_of<float>(get(client, "/api/rollouts/0/strain", "application/octet-stream"));
  ASSERT_EQ(strain.size(), expected_strain.size());
  for (std::size_t k = 0; k < strain.size(); ++k) EXPECT_NEAR(strain[k], expected_strain[k], 1e-6) << k;

  // Same grid and times: the distance is vertex to vertex, frame to frame.
  const auto distance = values_of<float>(get(client, "/api/rollouts/0/distance", "application/octet-stream"));
  ASSERT_EQ(distance.size(), static_cast<std::size_t>(T * N));
  for (int t = 0; t < T; ++t)
    for (int k = 0; k < N; ++k)
      EXPECT_NEAR(distance[t * N + k],
                  (frames.positions[t].segment<3>(3 * k) - reference.positions[t].segment<3>(3 * k)).norm(), 1e-6);
}

TEST_F(ViewerServerTest, ServesThePageAndThreeJs) {
  testing::RunningViewer viewer({rollout_, ""});
  httplib::Client client("127.0.0.1", viewer.port());
  EXPECT_NE(get(client, "/", "text/html").find("viewer.js"), std::string::npos);
  for (const char* path :
       {"/viewer.js", "/rollout_player.js", "/compare_chart.js", "/series_plots.js", "/colour_map.js",
        "/three/build/three.module.js", "/three/examples/jsm/controls/OrbitControls.js"})
    EXPECT_FALSE(get(client, path, "text/javascript").empty()) << path;
  EXPECT_FALSE(get(client, "/viewer.css", "text/css").empty());
}

// A mesh obstacle's arrays as they were loaded; an analytic obstacle, or one past the last, has none.
TEST(ViewerServerMesh, MeshObstacleEndpointsSendTheirArrays) {
  const testing::TempDir dir;
  const std::string path = (dir.path() / "mesh.h5").string();
  testing::write_mesh_obstacle_rollout(dir.path(), path, 3);
  const RolloutView view = load_rollout_view(path);
  testing::RunningViewer viewer({path, ""});
  httplib::Client client("127.0.0.1", viewer.port());
  for (int k = 0; k < 2; ++k) {
    const std::string obstacle = "/api/rollouts/0/obstacles/" + std::to_string(k);
    EXPECT_EQ(values_of<int>(get(client, obstacle + "/triangles", "application/octet-stream")),
              view.obstacles[k].triangles);
    EXPECT_EQ(values_of<float>(get(client, obstacle + "/vertices", "application/octet-stream")),
              view.obstacles[k].vertices);
  }
  for (const char* target : {"/api/rollouts/0/obstacles/2/triangles", "/api/rollouts/0/obstacles/3/vertices",
                             "/api/rollouts/1/obstacles/0/vertices", "/api/rollouts/0/obstacles/0/normals"})
    EXPECT_EQ(testing::raw_get_status(viewer.port(), target), 404) << target;
}

TEST_F(ViewerServerTest, AnythingOffTheWhitelistIs404) {
  testing::RunningViewer viewer({rollout_, ""});
  for (const std::string target : {"/../../etc/passwd",
                                   "/%2e%2e/%2e%2e/etc/passwd",
                                   "/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd",
                                   "//etc/passwd",
                                   "/etc/passwd",
                                   "/three/../../../../etc/passwd",
                                   "/three/build/../../../../../etc/passwd",
                                   "/three/build/three.js",
                                   "/three/%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
                                   "/index.html/../../CMakeLists.txt",
                                   "/viewer/web/index.html",
                                   "/rollout.h5",
                                   "/api/rollouts/0/../../../etc/passwd",
                                   "/api/rollouts/1/meta",
                                   "/api/rollouts/0/distance",
                                   "/api/rollouts/99999999999999/meta",
                                   "/api/rollouts/-1/meta",
                                   "/api/compare",
                                   "/api/rollouts/0/rest_positions",
                                   "/api/rollouts/0/obstacles/0/vertices",
                                   "/api/rollouts/0/obstacles/-1/triangles",
                                   "/favicon.ico",
                                   "/%00",
                                   "/viewer.js%00.html"})
    EXPECT_EQ(testing::raw_get_status(viewer.port(), target), 404) << target;
  EXPECT_EQ(testing::raw_get_status(viewer.port(), "/api/session"), 200) << "still serving";
  // Absolute URLs in the request line are refused too (400 or 404, never a file).
  const int absolute = testing::raw_get_status(viewer.port(), "http://127.0.0.1/etc/passwd");
  EXPECT_TRUE(absolute == 400 || absolute == 404) << absolute;
}

TEST_F(ViewerServerTest, APortInUseIsAOneLineError) {
  testing::RunningViewer first({rollout_, ""});
  ViewerServer second({rollout_, ""});
  try {
    second.listen_on("127.0.0.1", first.port());
    FAIL() << "bound a port in use";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("127.0.0.1:" + std::to_string(first.port())), std::string::npos) << message;
    EXPECT_NE(message.find("in use"), std::string::npos) << message;
  }
}

// The error's one line, "" if there was none.
std::string construction_error(const ViewerSource& source) {
  try {
    ViewerServer server(source);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST_F(ViewerServerTest, BadSourcesAreOneLineErrorsBeforeServing) {
  const testing::TempDir empty;
  const std::string text = empty.write("notes.txt", "hello\n");
  for (const auto& [source, says] : std::vector<std::pair<ViewerSource, std::string>>{
           {{(empty.path() / "missing.h5").string(), ""}, "no such file"},
           {{text, ""}, text},
           {{empty.path().string(), ""}, "no compare.csv"},
           {{empty.path().string(), rollout_}, "--against is for one rollout file"},
           {{rollout_, (empty.path() / "missing.h5").string()}, "no such file"}}) {
    const std::string error = construction_error(source);
    ASSERT_FALSE(error.empty()) << source.path;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_NE(error.find(says), std::string::npos) << error;
  }
}

TEST_F(ViewerServerTest, ACompareDirectoryServesItsTableAndKeptRollouts) {
  const testing::TempDir dir;
  const auto d = dir.path();
  // As compare --keep-rollouts leaves them: the kept run's rollout and its scene's reference,
  // beside a reference of another scene under the same label (another hash).
  testing::write_test_rollout((d / "rollout_pqn_10_6x8_xy_v2.h5").string(), 6, 8, 10);
  testing::write_test_rollout((d / "newton_reference_6x8_xy_v2_fedcba9876543210.h5").string(), 6, 8, 4);
  testing::write_test_rollout((d / "newton_reference_6x8_xy_v2_0123456789abcdef.h5").string(), 6, 8, 10);
  CsvTable table({"method", "N", "resolution", "motion", "ms_per_frame", "e_cd_x1e3", "frontier", "note"});
  table.add_row({"pqn", "10", "6x8", "xy_v2", "1.5", "0.3", "yes", ""});
  table.add_row({"lbfgs", "100", "6x8", "xy_v2", "9.5", "0.1", "yes", "not kept"});
  table.write((d / "compare.csv").string());

  testing::RunningViewer viewer({d.string(), ""});
  httplib::Client client("127.0.0.1", viewer.port());
  EXPECT_EQ(get(client, "/api/session", "application/json"), "{\"mode\":\"compare\"}");
  const std::string compare = get(client, "/api/compare", "application/json");
  EXPECT_NE(compare.find("{\"cells\":[\"pqn\",\"10\",\"6x8\",\"xy_v2\",\"1.5\",\"0.3\",\"yes\",\"\"],"
                         "\"rollout\":\"rollout_pqn_10_6x8_xy_v2.h5\","
                         "\"reference\":\"newton_reference_6x8_xy_v2_0123456789abcdef.h5\"}"),
            std::string::npos)
      << compare;
  EXPECT_NE(compare.find("\"not kept\"],\"rollout\":null,\"reference\":null}"), std::string::npos) << compare;

  const std::string meta = get(client, "/api/rollouts/0/meta", "application/json");
  EXPECT_NE(meta.find("\"frames\":11"), std::string::npos) << meta;
  // The kept rollout against its own scene's reference: the same solver, so distance 0.
  for (const float d : values_of<float>(get(client, "/api/rollouts/0/distance", "application/octet-stream")))
    EXPECT_NEAR(d, 0.0f, 1e-6);
  EXPECT_EQ(testing::raw_get_status(viewer.port(), "/api/rollouts/1/meta"), 404) << "a run not kept";
  EXPECT_EQ(testing::raw_get_status(viewer.port(), "/newton_reference_6x8_xy_v2_0123456789abcdef.h5"), 404);
  EXPECT_EQ(testing::raw_get_status(viewer.port(), "/compare.csv"), 404);
}

}  // namespace
}  // namespace fnopt
