#include <fnopt/viewer/viewer_server.hpp>

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include <fnopt/util/error.hpp>
#include <fnopt/viewer/compare_directory.hpp>
#include <fnopt/viewer/rollout_view.hpp>
#include <fnopt/viewer/web_assets.hpp>

namespace fnopt {

namespace {

const char* const kJson = "application/json";
const char* const kBinary = "application/octet-stream";

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  require(static_cast<bool>(in), path, "cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Sends `size` bytes from `data`, which `owner` keeps alive, as they are. httplib would compress
// a body set with set_content for a browser that accepts Brotli, at its slowest setting: far
// more time than a local connection saves (docs/design.md §11). Nor is a large payload copied
// into the response.
void send_uncompressed(httplib::Response& response, std::shared_ptr<const void> owner, const char* data,
                       std::size_t size, const std::string& content_type) {
  response.set_content_provider(size, content_type,
                                [owner, data](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                                  return sink.write(data + offset, length);
                                });
}

template <class Number>
void send_binary(httplib::Response& response, const std::shared_ptr<const RolloutView>& view,
                 const std::vector<Number>& values) {
  send_uncompressed(response, view, reinterpret_cast<const char*>(values.data()), values.size() * sizeof(Number),
                    kBinary);
}

}  // namespace

struct ViewerServer::State {
  httplib::Server server;
  std::map<std::string, std::pair<std::string, std::string>> files;  // URL -> content, type; never changed
  // One rollout (id 0), or a compare directory whose kept rollouts are loaded when asked for.
  std::shared_ptr<const RolloutView> rollout;
  std::unique_ptr<CompareDirectory> directory;
  std::mutex cache_mutex;
  std::vector<std::pair<std::size_t, std::shared_ptr<const RolloutView>>> cache;  // most recent last
  std::mutex run_mutex;
  bool stop_requested = false, serving = false;
  std::atomic<bool> finished{false};

  // The rollout with this id, nullptr if there is none.
  std::shared_ptr<const RolloutView> rollout_with_id(std::size_t id) {
    if (rollout) return id == 0 ? rollout : nullptr;
    if (id >= directory->runs.size() || directory->runs[id].rollout.empty()) return nullptr;
    const std::lock_guard<std::mutex> lock(cache_mutex);
    for (std::size_t k = 0; k < cache.size(); ++k)
      if (cache[k].first == id) {
        std::rotate(cache.begin() + k, cache.begin() + k + 1, cache.end());
        return cache.back().second;
      }
    // Two rollouts of 100x100 x 391 frames hold ~150 MB: enough for going back and forth.
    if (cache.size() == 2) cache.erase(cache.begin());
    const CompareRun& run = directory->runs[id];
    cache.emplace_back(id, std::make_shared<const RolloutView>(load_rollout_view(run.rollout, run.reference)));
    return cache.back().second;
  }

  void add_routes() {
    server.Get("/api/session", [this](const httplib::Request&, httplib::Response& response) {
      response.set_content(rollout ? "{\"mode\":\"rollout\",\"rollout\":0}" : "{\"mode\":\"compare\"}", kJson);
    });
    server.Get("/api/compare", [this](const httplib::Request&, httplib::Response& response) {
      if (!directory) {
        response.status = 404;
        return;
      }
      response.set_content(compare_directory_json(*directory), kJson);
    });
    server.Get(R"(/api/rollouts/(\d{1,9})/(meta|positions|faces|strain|distance))",
               [this](const httplib::Request& request, httplib::Response& response) {
                 const auto view = rollout_with_id(std::stoul(request.matches[1].str()));
                 const std::string part = request.matches[2].str();
                 if (!view || (part == "distance" && view->distance.empty())) {
                   response.status = 404;
                   return;
                 }
                 if (part == "meta") response.set_content(rollout_metadata_json(*view), kJson);
                 if (part == "positions") send_binary(response, view, view->positions);
                 if (part == "faces") send_binary(response, view, view->faces);
                 if (part == "strain") send_binary(response, view, view->strain);
                 if (part == "distance") send_binary(response, view, view->distance);
               });
    // A mesh obstacle's arrays (rollout_view.hpp); an analytic one has none.
    server.Get(R"(/api/rollouts/(\d{1,9})/obstacles/(\d{1,9})/(triangles|vertices))",
               [this](const httplib::Request& request, httplib::Response& response) {
                 const auto view = rollout_with_id(std::stoul(request.matches[1].str()));
                 const std::size_t k = std::stoul(request.matches[2].str());
                 if (!view || k >= view->obstacles.size() || view->obstacles[k].triangles.empty()) {
                   response.status = 404;
                   return;
                 }
                 const ObstacleView& obstacle = view->obstacles[k];
                 if (request.matches[3].str() == "triangles")
                   send_binary(response, view, obstacle.triangles);
                 else
                   send_binary(response, view, obstacle.vertices);
               });
    // Everything else: one of the page's files by its exact URL, or 404.
    server.Get(R"(/.*)", [this](const httplib::Request& request, httplib::Response& response) {
      const auto file = files.find(request.path == "/" ? "/index.html" : request.path);
      if (file == files.end()) {
        response.status = 404;
        return;
      }
      send_uncompressed(response, nullptr, file->second.first.data(), file->second.first.size(), file->second.second);
    });
    server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
      if (response.body.empty()) response.set_content(response.status == 404 ? "not found\n" : "error\n", "text/plain");
    });
    // A rollout of a compare directory that fails to load answers with its one-line error.
    server.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
      response.status = 500;
      try {
        std::rethrow_exception(error);
      } catch (const std::exception& e) {
        response.set_content(std::string(e.what()) + "\n", "text/plain");
      }
    });
  }
};

ViewerServer::ViewerServer(const ViewerSource& source) : state_(std::make_unique<State>()) {
  const bool is_directory = std::filesystem::is_directory(source.path);
  require(!is_directory || source.against.empty(), "against",
          "a compare directory brings its own Newton references; --against is for one rollout file");
  for (const WebAsset& asset : find_web_assets())
    state_->files[asset.url] = {file_text(asset.file), asset.content_type};
  if (is_directory)
    state_->directory = std::make_unique<CompareDirectory>(read_compare_directory(source.path));
  else
    state_->rollout = std::make_shared<const RolloutView>(load_rollout_view(source.path, source.against));
  state_->add_routes();
}

ViewerServer::~ViewerServer() = default;

int ViewerServer::listen_on(const std::string& host, int port) {
  // httplib's default also sets SO_REUSEPORT, with which a second server on a port in use would
  // bind too and share it silently; SO_REUSEADDR alone only allows a restart after a quit.
  state_->server.set_socket_options([](socket_t socket) {
    const int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  const int bound =
      port == 0 ? state_->server.bind_to_any_port(host) : (state_->server.bind_to_port(host, port) ? port : -1);
  require(bound > 0, "port",
          "cannot listen on " + host + ":" + std::to_string(port) +
              " (the port is in use, or the host is not an address of this machine); "
              "--port and --host choose others");
  return bound;
}

// httplib's stop() does nothing until its accept loop runs, so a stop() right after serve()
// starts would be lost: stop() waits for the loop, or keeps serve() from starting it.
void ViewerServer::serve() {
  {
    const std::lock_guard<std::mutex> lock(state_->run_mutex);
    if (state_->stop_requested) return;
    state_->serving = true;
  }
  state_->server.listen_after_bind();
  state_->finished = true;
}

void ViewerServer::stop() {
  {
    const std::lock_guard<std::mutex> lock(state_->run_mutex);
    state_->stop_requested = true;
    if (!state_->serving) return;
  }
  while (!state_->server.is_running() && !state_->finished) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  state_->server.stop();
}

}  // namespace fnopt
