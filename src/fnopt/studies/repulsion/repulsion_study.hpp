#pragma once
// `fnopt repulsion-study` (docs/design.md §8 "Self-contact"): self-repulsion off and on, on the
// handle presets whose cloth folds onto itself (corner-center, single-mid-edge) and on the corner
// control. Per run: the repulsive energy of every frame under a fixed reference barrier and the
// penetration proxies of metrics/self_contact.hpp. Writes, after every run, DIR/repulsion.csv (one
// row per run), DIR/repulsion_energy.csv (the energy of every frame of every run, for the plot)
// and, at the end, DIR/repulsion.svg (energy over time) and DIR/report.md. --resume keeps the
// runs already in both files (same preset, repulsion and optimizer).
#include <string>
#include <vector>

#include <fnopt/methods/registry.hpp>
#include <fnopt/parallel/communicator.hpp>
#include <fnopt/scenes/scene.hpp>

namespace fnopt {

struct RepulsionStudy {
  Scene base;                               // grid, motion, frames, repulsion stiffness; validated
  std::vector<OptimizerChoice> optimizers;  // names and models checked by the caller
  std::string out;                          // the output directory (made and checked writable)
  std::string command_line;                 // for report.md
  int threads = 1;                          // in effect (set by the caller)
  bool resume = false;
};

// corner-center, single-mid-edge (fold onto themselves), corner (the control).
const std::vector<std::string>& repulsion_presets();

// With more than one process (mpirun, srun), the runs are spread over the ranks largest first
// (parallel/sweep_schedule.hpp); rank 0 writes the outputs exactly as one process would. DIR
// must be one shared folder.
void run_repulsion_study(const RepulsionStudy& study, const Communicator& comm = Communicator::world());

}  // namespace fnopt
