// fnopt bench: flags only; the timing tables are studies/bench/bench_run.hpp (docs/design.md §9).
#include <sstream>

#include <fnopt/studies/bench/bench_run.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include "app/commands.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct BenchFlags {
  BenchRun run;
  std::string resolution_list = "32,64,100";
  int threads = 0;  // the default: set_thread_count
};

std::vector<int> parse_resolutions(const std::string& list) {
  std::vector<int> values;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    int n = 0;
    require(parse_int(item, n) && n >= 3, "res", "expected a comma-separated list of sizes >= 3, got '" + list + "'");
    values.push_back(n);
  }
  return values;
}

void run_bench_command(BenchFlags& flags) {
  flags.run.threads = set_thread_count(flags.threads);
  flags.run.resolutions = parse_resolutions(flags.resolution_list);
  run_bench(flags.run);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* command =
      app.add_subcommand("bench", "timing tables: the Newton step, the FNO passes, a rollout's adjoint, contact's cost, the angle "
                         "kernels");
  command
      ->add_option("what", flags->run.what,
                   "newton, fno, adjoint (a recorded rollout's forward and backward passes), contact (pqn and newton "
                   "with far obstacles, a far mesh and self-contact, each against the same scene without), kernels (the "
                   "angle springs' gradient, stencils per second, scalar and SIMD), speed (pqn 10, fnopt 10 and newton with 1 "
                   "and 2 threads, ms/frame, evaluations per frame and peak memory beside fnopt 1.0's) or all (newton "
                   "and fno)")
      ->capture_default_str();
  command->add_option("--res", flags->resolution_list, "resolutions, comma-separated")->capture_default_str();
  command->add_option("--model", flags->run.model, "fno: the model whose shape is timed (default: the shipped model)");
  command->add_option("--frames", flags->run.frames, "frames per resolution (newton, adjoint, contact)")
      ->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command
      ->add_option(
          "--keep", flags->run.keep,
          "newton: also write each rollout to DIR/newton_<res>.h5 (an existing directory; with --repeat, the first "
          "run's)")
      ->check(CLI::ExistingDirectory);
  command->add_flag("--warm-start", flags->run.warm_start, "start each step from the previous acceleration");
  command
      ->add_option("--repeat", flags->run.repeat,
                   "newton, contact, speed: time each resolution this many times; the table gives the medians "
                   "(newton: and ms/frame's range)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command
      ->add_option("--preconditioner", flags->run.preconditioner,
                   "newton: CG's preconditioner: auto (P's Cholesky factor, on fine grids a multigrid V-cycle), "
                   "factor or multigrid at every grid")
      ->capture_default_str();
  // speed's own: one row, measured in the process the table starts for it.
  command->add_option("--row", flags->run.row, "speed: one METHOD[:ITERATIONS] in this process")->group("");
  command->callback([flags] { run_bench_command(*flags); });
});

}  // namespace
}  // namespace fnopt::app
