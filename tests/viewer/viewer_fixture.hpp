#pragma once
// What the viewer's tests share: small rollout files made by a real solver (one beside mesh
// obstacles read from OBJ files it writes), a server running on an ephemeral port in a thread, raw
// HTTP requests (exactly the bytes given, no client-side normalisation of the path) and reading
// numbers back out of the JSON endpoints.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fnopt/baselines/pqn.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/viewer/viewer_server.hpp>

namespace fnopt::testing {

// A rows x cols cloth swinging for `frames` steps beside `obstacles` (a scene file's obstacle
// value; "" for none).
inline Scene test_scene(int rows, int cols, int frames, const std::string& motion = "xy_v2",
                        const std::string& obstacles = "") {
  Scene scene;
  scene.rows = rows;
  scene.cols = cols;
  scene.frames = frames;
  scene.motion = motion;
  if (!obstacles.empty()) apply_scene_setting(scene, "obstacle", obstacles);
  return scene;
}

// The scene's rollout (pqn, 10 iterations), written to `path`.
inline void write_scene_rollout(const std::string& path, const Scene& scene) {
  PqnOptimizer pqn;
  RolloutOptions options;
  options.solve.max_iterations = 10;
  const RolloutResult rollout = run_rollout(resolve(scene), pqn, options);
  write_rollout_file(path, rollout, to_scene_text(scene), pqn.settings());
}

// test_scene's rollout, written to `path`.
inline void write_test_rollout(const std::string& path, int rows, int cols, int frames,
                               const std::string& motion = "xy_v2", const std::string& obstacles = "") {
  write_scene_rollout(path, test_scene(rows, cols, frames, motion, obstacles));
}

// A tetrahedron's OBJ: the corner at the origin and the three 0.2 m along the axes, all moved
// `shift` m along x; its triangles face outwards.
inline std::string tetrahedron_obj(double shift) {
  std::string text;
  for (const auto& [x, y, z] : {std::array{0.0, 0.0, 0.0}, {0.2, 0.0, 0.0}, {0.0, 0.2, 0.0}, {0.0, 0.0, 0.2}})
    text += "v " + std::to_string(x + shift) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
  return text + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

// A 6x6 cloth swinging for `frames` steps beside three obstacles, written to `path`, their files
// to `dir`: a static tetrahedron (mesh file=), an animated one (a sequence of three frames at
// 20 fps, walking along x) that also follows a path along z, and a plane below. Returns the scene.
inline Scene write_mesh_obstacle_rollout(const std::filesystem::path& dir, const std::string& path, int frames) {
  const std::string obj = (dir / "tetrahedron.obj").string(), prefix = (dir / "walk").string();
  std::ofstream(obj) << tetrahedron_obj(0.0);
  for (int k = 0; k < 3; ++k) std::ofstream(prefix + "000" + std::to_string(k) + ".obj") << tetrahedron_obj(0.1 * k);
  std::ofstream(dir / "path.csv") << "t,x,y,z\n0,0.4,-1.5,-0.5\n1,0.4,-1.5,-0.2\n";
  const Scene scene = test_scene(6, 6, frames, "xy_v2",
                                 "mesh file=" + obj + " offset=0.4,1.5,-0.5;mesh sequence=" + prefix +
                                     " fps=20 offset=0.4,-1.5,-0.5 path=" + (dir / "path.csv").string() +
                                     ";plane point=0,0,-3 normal=0,0,1");
  write_scene_rollout(path, scene);
  return scene;
}

// A ViewerServer answering on 127.0.0.1 at port() until destroyed.
class RunningViewer {
 public:
  explicit RunningViewer(const ViewerSource& source) : server_(source) {
    port_ = server_.listen_on("127.0.0.1", 0);
    thread_ = std::thread([this] { server_.serve(); });
  }
  ~RunningViewer() {
    server_.stop();
    thread_.join();
  }
  int port() const { return port_; }
  ViewerServer& server() { return server_; }

 private:
  ViewerServer server_;
  int port_ = 0;
  std::thread thread_;
};

// The status code of "GET <target>" sent as is; -1 if there was no answer.
inline int raw_get_status(int port, const std::string& target) {
  const int socket_fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(socket_fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    close(socket_fd);
    return -1;
  }
  const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  if (write(socket_fd, request.data(), request.size()) != static_cast<ssize_t>(request.size())) {
    close(socket_fd);
    return -1;
  }
  std::string answer;
  char buffer[4096];
  for (ssize_t n; (n = read(socket_fd, buffer, sizeof buffer)) > 0;) answer.append(buffer, n);
  close(socket_fd);
  // "HTTP/1.1 404 Not Found"
  return answer.compare(0, 5, "HTTP/") == 0 && answer.size() > 12 ? std::atoi(answer.c_str() + 9) : -1;
}

// The numbers of the JSON array that follows "key": in `json` (null as NaN); empty if absent.
inline std::vector<double> json_numbers(const std::string& json, const std::string& key) {
  std::vector<double> numbers;
  const auto at = json.find("\"" + key + "\":[");
  if (at == std::string::npos) return numbers;
  const char* p = json.c_str() + at + key.size() + 4;
  while (*p != ']') {
    if (std::string(p, 4) == "null") {
      numbers.push_back(std::nan(""));
      p += 4;
    } else {
      char* end = nullptr;
      numbers.push_back(std::strtod(p, &end));
      p = end;
    }
    if (*p == ',') ++p;
  }
  return numbers;
}

// The bytes of an endpoint's binary answer as values of type T.
template <class T>
std::vector<T> values_of(const std::string& body) {
  std::vector<T> values(body.size() / sizeof(T));
  std::copy(body.begin(), body.end(), reinterpret_cast<char*>(values.data()));
  return values;
}

}  // namespace fnopt::testing
