#pragma once
// The viewer's local web server (docs/design.md §11): the page's files and a few data endpoints
// for one rollout (`fnopt view FILE [--against REF]`) or for a compare directory and its kept
// rollouts (`fnopt view DIR`). Routes are a whitelist; no URL is ever turned into a path, so
// nothing but those files and the viewed data can be sent, and any other request is a 404.
#include <memory>
#include <string>

namespace fnopt {

struct ViewerSource {
  std::string path;     // a rollout file, or a compare output directory
  std::string against;  // a reference file for a rollout's distances, "" for none
};

class ViewerServer {
 public:
  // Reads the page's files and the viewed data now (a rollout whole, a directory's compare.csv),
  // so that every error is an Error naming the file before anything is served.
  explicit ViewerServer(const ViewerSource& source);
  ~ViewerServer();
  ViewerServer(const ViewerServer&) = delete;
  ViewerServer& operator=(const ViewerServer&) = delete;

  // Binds `host`:`port` (port 0: any free port) and returns the port. Throws Error if it cannot
  // (a port in use, a host that is not an address of this machine).
  int listen_on(const std::string& host, int port);
  // Answers requests until stop(); call after listen_on.
  void serve();
  // Thread-safe; serve() returns soon after.
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace fnopt
