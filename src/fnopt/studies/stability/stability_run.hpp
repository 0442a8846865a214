#pragma once
// One run of the stability suite and its measured row: a rollout of a case's scene, or the
// error that stopped it, against the case's Newton reference (the energy growth is defined in
// studies/stability/stability_suite.hpp).
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {

// Makes a fresh optimizer by method name ("newton", "gd", ...); may throw.
using OptimizerFactory = std::function<std::unique_ptr<InnerOptimizer>(const std::string& method)>;

struct StabilityMethod {
  std::string method;       // the name the factory knows
  InnerSolveOptions solve;  // budget (and tolerance) per time step
  bool reference = false;   // the exact solver every case is measured against (Newton)
};

// One rollout of a scene, or the error that stopped it (an exception from the factory, the scene
// or the optimizer: recorded, never rethrown).
struct StabilityRun {
  RolloutResult rollout;
  double initial_energy = NAN;  // E_0, the rest state's total energy [J]
  int frames_requested = 0;
  bool failed = false;
  std::string error;
};

StabilityRun run_stability_rollout(const Scene& scene, const StabilityMethod& method, const OptimizerFactory& factory,
                                   const RolloutOptions& base_options = {}, const StepCallback& on_step = {});

enum class StabilityOutcome { Finished, Diverged, Error };
const char* to_string(StabilityOutcome outcome);  // "finished", "diverged", "error"

struct StabilityRow {
  std::string case_name, method;
  bool reference = false;  // StabilityMethod::reference (not in the CSV: set by the caller)
  InnerSolveOptions solve;
  StabilityOutcome outcome = StabilityOutcome::Error;
  int frames_done = 0;  // steps finished before a divergence
  int frames_requested = 0;
  int diverged_step = 0;       // the step that diverged (1-based), 0 if none
  std::string reason;          // RolloutResult::divergence or the error's message
  double max_strain = NAN;     // largest edge strain over the finite steps
  double energy_growth = NAN;  // see the top of this file; NaN without a reference
  double e3d = NAN;            // e_3D against the case's Newton reference (raw, not x 10^2)
  double ms_per_frame = NAN;   // ms_per_frame()
  double iterations_per_frame = NAN;
  int unconverged_steps = 0;         // see count_unconverged_steps
  std::string unconverged_statuses;  // "iteration-budget x2, line-search-failed x1", "" if none
  // On a case with contact (obstacles or self-contact), the exact self-intersection count of the
  // frames as stored and, with a mesh obstacle, the mesh intersection count (count_intersections);
  // -1 where not measured.
  long self_intersections = -1, mesh_intersections = -1;
};

// Measures a run against the case's Newton reference (nullptr, failed or empty: no e_3D and no
// energy growth). Never produces NaN in a field that the run defines.
StabilityRow stability_row(const std::string& case_name, const StabilityMethod& method, const StabilityRun& run,
                           const StabilityRun* reference);

// Fills the row's intersection counts from the run's frames where `scene` has contact.
void count_intersections(const Scene& scene, const StabilityRun& run, StabilityRow& row);

// Steps that stopped for a reason other than convergence. With a tolerance (Newton) every step
// short of it counts; with a fixed budget (tolerance 0) using the whole budget is the normal end,
// so only other reasons count (line-search-failed, non-finite, ...). Fills `statuses` with
// "status xN" entries.
int count_unconverged_steps(const RolloutResult& rollout, const InnerSolveOptions& solve, std::string& statuses);
// (max E - E_min) / (max E_ref - E_min) as above; NaN if undefined.
double energy_growth(const StabilityRun& run, const StabilityRun& reference);

}  // namespace fnopt
