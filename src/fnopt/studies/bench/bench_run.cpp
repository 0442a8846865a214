#include <fnopt/studies/bench/bench_run.hpp>

#include <cstdio>
#include <sstream>

#include <fnopt/fno/fno_bench.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/studies/bench/bench_adjoint.hpp>
#include <fnopt/studies/bench/bench_contact.hpp>
#include <fnopt/studies/bench/bench_kernels.hpp>
#include <fnopt/studies/bench/bench_newton.hpp>
#include <fnopt/studies/bench/bench_speed.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

void bench_fno_table(const BenchRun& run) {
  std::ostringstream table;
  const std::string model = run.model.empty() ? shipped_model_path() : run.model;
  std::printf("FNO of %s\n", model.c_str());
  run_fno_bench(table, run.threads, load_fno_options(model), run.resolutions);
  std::printf("%s", table.str().c_str());
}

}  // namespace

void run_bench(const BenchRun& run) {
  if (run.what != "newton" && run.what != "fno" && run.what != "adjoint" && run.what != "contact" &&
      run.what != "kernels" && run.what != "speed" && run.what != "all")
    throw Error("bench",
                "unknown benchmark '" + run.what + "' (choose newton, fno, adjoint, contact, kernels, speed or all)");
  if (run.what == "newton" || run.what == "all") bench_newton_table(run);
  if (run.what == "fno" || run.what == "all") bench_fno_table(run);
  if (run.what == "adjoint") bench_adjoint_table(run);
  if (run.what == "contact") bench_contact_table(run);
  if (run.what == "kernels") bench_kernels_table(run);
  if (run.what == "speed") bench_speed_table(run);
}

}  // namespace fnopt
