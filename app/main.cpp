// fnopt: the command line. Each subcommand lives in its own source (app/*_command.cpp) and
// registers itself here; an Error from anywhere, or a flag the parser rejects, becomes one
// line on stderr and exit code 2.
// So does any other exception (a filesystem error for an --out that is a file, say): its first
// line only, since some libraries append a backtrace.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>

#include "app/commands.hpp"
#include "util/error.hpp"
#include "util/retained_heap.hpp"

int main(int argc, char** argv) {
  fnopt::retain_freed_heap_memory();
  CLI::App app{"fnopt: grid cloth with a learned Fourier-neural-operator optimizer"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(FNOPT_VERSION));
  for (const auto& add : fnopt::app::command_registry()) add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // A flag the parser rejects: one line and status 2, as every other error (CLI11's own exit
    // codes, 104-114, and its second line "Run with --help" would break that promise).
    const std::string what = e.what();
    std::cerr << "fnopt: error: " << what.substr(0, what.find('\n')) << " (see --help)\n";
    return 2;
  } catch (const fnopt::Error& e) {
    std::cerr << "fnopt: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    const std::string what = e.what();
    std::cerr << "fnopt: error: " << what.substr(0, what.find('\n')) << "\n";
    return 2;
  }
  return 0;
}
