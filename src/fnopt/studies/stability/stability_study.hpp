#pragma once
// `fnopt stability`'s study (docs/design.md §8 "Stability"): the cases of
// studies/stability/stability_suite.hpp, every optimizer on every case, one table. Per case: the Newton
// reference rollout, then every optimizer; per row: finished / diverged (step, why) / error, max
// strain, energy growth, e_3D against the reference, ms/frame, steps short of convergence.
// Writes DIR/stability.csv (after every row), DIR/stability.svg and DIR/report.md (after every
// case), and prints the table at the end.
#include <string>
#include <vector>

#include <fnopt/parallel/communicator.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/studies/stability/stability_suite.hpp>

namespace fnopt {

struct StabilityStudy {
  Scene base;                             // every case applied to it validates
  std::vector<StabilityCase> cases;       // in report order
  std::vector<std::string> method_names;  // as given, for the plot's series
  std::vector<StabilityMethod> methods;   // each with its budget; names known to the registry
  std::string model;                      // learned optimizer weights, "" for the shipped model
  std::string out;                        // the output directory (made and checked writable)
  std::string command_line;               // for report.md
  int threads = 1;                        // in effect (set by the caller), printed with every timing
  bool resume = false;                    // keep DIR/stability.csv's rows of the same case, method, N
};

// With more than one process (mpirun, srun), the cases are spread over the ranks largest first
// (parallel/sweep_schedule.hpp), each with its Newton reference, which its rows are measured
// against; rank 0 writes the outputs exactly as one process would (the same rows in the same
// order) after every case that finishes anywhere. DIR must be one shared folder.
void run_stability_study(const StabilityStudy& study, const Communicator& comm = Communicator::world());

}  // namespace fnopt
