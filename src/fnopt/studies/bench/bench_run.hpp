#pragma once
// `fnopt bench`: timing tables measured in one run (docs/design.md §9): the Newton reference step
// at several resolutions (bench_newton.hpp), the FNO's passes (fno/fno_bench.hpp), a rollout's
// adjoint (bench_adjoint.hpp, §15), the contact term's cost with far obstacles
// (bench_contact.hpp, §14), the angle springs' gradient throughput (bench_kernels.hpp) and every
// method's ms/frame, evaluations and memory beside 1.0's (bench_speed.hpp). Each prints its table to
// stdout as it goes, with progress bars.
#include <string>
#include <vector>

namespace fnopt {

struct BenchRun {
  std::string what = "newton";  // newton, fno, adjoint, contact, kernels, speed or all (newton and fno)
  std::vector<int> resolutions = {32, 64, 100};
  int frames = 390;  // per resolution (newton, adjoint, contact)
  int threads = 1;   // the thread count in effect, for the headers
  bool warm_start = false;
  std::string keep;   // newton: a directory for each resolution's rollout, or empty
  std::string model;  // fno: the model whose shape is timed; empty: the shipped model
  std::string preconditioner = "auto";  // newton: auto, factor or multigrid
  int repeat = 1;                       // newton, contact, speed: timed runs per resolution
  std::string row;  // speed: one method of the table ("pqn:10"), measured in this process
};

// Throws Error("bench", ...) for an unknown table, Error("preconditioner", ...) for an unknown
// preconditioner.
void run_bench(const BenchRun& run);

}  // namespace fnopt
