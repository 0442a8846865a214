// fnopt: the command line. Each subcommand lives in its own source (app/*_command.cpp) and
// registers itself here; an Error from anywhere, or a flag the parser rejects, becomes one
// line on stderr and exit code 2.
// So does any other exception (a filesystem error for an --out that is a file, say): its first
// line only, since some libraries append a backtrace.
#include <CLI/CLI.hpp>
#include <chrono>
#include <exception>
#include <iostream>
#include <string>
#include <thread>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/retained_heap.hpp>
#include <fnopt/version.hpp>
#include "app/commands.hpp"

namespace {

// The error's one line. Run by mpirun or srun, the first rank to fail stops every rank
// (MPI_Abort): the others may be waiting for it in a collective and would wait forever. Its
// message names the rank; every rank of a run with a bad flag fails alike, so rank 0 speaks for
// them and the others stay quiet for a moment, long enough for rank 0's abort to reach them.
int fail(const std::string& line) {
  const fnopt::Communicator& world = fnopt::Communicator::world();
  if (world.size() == 1) {
    std::cerr << "fnopt: error: " << line << "\n";
    return 2;
  }
  if (!world.is_root()) std::this_thread::sleep_for(std::chrono::seconds(2));
  std::cerr << "fnopt: error (rank " << world.rank() << " of " << world.size() << "): " << line << std::endl;
  world.abort(2);
}

}  // namespace

int main(int argc, char** argv) {
  fnopt::retain_freed_heap_memory();
  const fnopt::MpiSession mpi(argc, argv);
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
    return fail(what.substr(0, what.find('\n')) + " (see --help)");
  } catch (const fnopt::Error& e) {
    return fail(e.what());
  } catch (const std::exception& e) {
    const std::string what = e.what();
    return fail(what.substr(0, what.find('\n')));
  }
  return 0;
}
