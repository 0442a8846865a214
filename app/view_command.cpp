// fnopt view: a local web viewer of a rollout (against a reference) or of a compare directory
// (docs/design.md §11). Everything is checked and loaded before the address is printed.
#include <cstdio>
#include <memory>
#include <string>

#include <fnopt/viewer/viewer_server.hpp>
#include "app/commands.hpp"

namespace fnopt::app {
namespace {

struct ViewFlags {
  ViewerSource source;
  std::string host = "127.0.0.1";
  int port = 8080;
};

void run_view(const ViewFlags& flags) {
  ViewerServer server(flags.source);
  const int port = server.listen_on(flags.host, flags.port);
  std::printf("fnopt view: http://%s:%d/ (Ctrl-C to stop)\n", flags.host.c_str(), port);
  std::fflush(stdout);
  server.serve();
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<ViewFlags>();
  CLI::App* command =
      app.add_subcommand("view", "view a rollout, or a compare output directory, in the browser (a local web server)");
  command->add_option("path", flags->source.path, "a rollout file (HDF5, fnopt or ARCSim) or a compare directory")
      ->required();
  command->add_option("--against", flags->source.against,
                      "a reference rollout: colour the cloth by each vertex's distance to it");
  command->add_option("--port", flags->port, "TCP port (0: any free port)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  command->add_option("--host", flags->host, "address to listen on (0.0.0.0: every interface)")->capture_default_str();
  command->callback([flags] { run_view(*flags); });
});

}  // namespace
}  // namespace fnopt::app
