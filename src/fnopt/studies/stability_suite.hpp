#pragma once
// The stability study (docs/design.md §8 "Stability"; `fnopt stability`): a fixed suite of
// stiff and extreme cases, each a change of a base scene (the default: 32^2, corner handles,
// xy_v2, the default material, dt = 1/60), every inner optimizer on every case, one row per
// case x optimizer. Optimizers come from a factory: the study (studies/stability_study.hpp) makes
// them by name through the registry, tests inject their own.
//
// Per row: finished / diverged (the step, and RolloutResult::divergence) / error (an exception:
// the suite goes on), max edge strain, energy growth, e_3D against the case's Newton reference,
// ms/frame, iterations per frame, and the steps that stopped for a reason other than convergence
// (for Newton, which must never fail silently, every step short of its tolerance).
//
// Energy growth: with E(t) the total energy (kinetic + potential, StepRecord::energy) and E_0 the
// energy of the initial rest state, and E_min the lowest energy of the Newton reference (E_0
// included),
//     growth = (max_t E(t) - E_min) / (max_t E_ref(t) - E_min)      (maxima include E_0)
// i.e. the run's energy peak over the reference's, both measured from the reference's floor
// (gravity makes E negative, so a plain ratio of peaks means nothing). 1 for the reference
// itself and ~1 for a healthy run; >> 1 for a blow-up (a diverging step's elastic energy
// counts); < 1 for a run that loses energy (under-solved steps dissipate).
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/rollout_file.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/optimizer/inner_optimizer.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>

namespace fnopt {

// ---- The cases -------------------------------------------------------------------------------

struct StabilityCase {
  std::string name;                          // "stretch-x100"
  std::string description;                   // one line for reports
  std::vector<std::string> fields;           // Scene fields it changes: "material.stretch", "material.shear",
                                             // "material.bend", "speed", "dt", "handles", "rows", "cols",
                                             // "frames"; empty for the baseline (the base scene itself)
  std::function<Scene(const Scene&)> apply;  // base scene -> the case's scene
};

// The suite, in report order: baseline; stretch x10, x100, x1000; soft (stretch and shear x0.1);
// bend x100, x0.01; speed x1.2, x1.5, x2, x4; dt 1/24, 1/240 (frames scaled to keep the base's
// simulated time); every other handle preset (the baseline is `corner`); 128^2 and 200^2 grids
// (on the first fifth and tenth of the base's frames: see the descriptions).
const std::vector<StabilityCase>& stability_cases();
std::vector<std::string> stability_case_names();
// The cases named in a comma-separated list, in its order, duplicates dropped; "" or "all":
// every case. Throws Error("cases", "unknown case 'x' (choose from: ...)").
std::vector<StabilityCase> select_stability_cases(const std::string& list);

// ---- Running ---------------------------------------------------------------------------------

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
};

// Measures a run against the case's Newton reference (nullptr, failed or empty: no e_3D and no
// energy growth). Never produces NaN in a field that the run defines.
StabilityRow stability_row(const std::string& case_name, const StabilityMethod& method, const StabilityRun& run,
                           const StabilityRun* reference);

// Steps that stopped for a reason other than convergence. With a tolerance (Newton) every step
// short of it counts; with a fixed budget (tolerance 0) using the whole budget is the normal end,
// so only other reasons count (line-search-failed, non-finite, ...). Fills `statuses` with
// "status xN" entries.
int count_unconverged_steps(const RolloutResult& rollout, const InnerSolveOptions& solve, std::string& statuses);
// (max E - E_min) / (max E_ref - E_min) as above; NaN if undefined.
double energy_growth(const StabilityRun& run, const StabilityRun& reference);

// ---- Results ---------------------------------------------------------------------------------

// The CSV columns of DIR/stability.csv, one row per case x method.
const std::vector<std::string>& stability_columns();
std::vector<std::string> stability_csv_row(const StabilityRow& row);
// A row of an earlier stability.csv back into a result (--resume). Throws Error on a wrong width.
StabilityRow stability_row_from_csv(const std::vector<std::string>& cells);
// "N=100", "tol 1e-09 (max 1000)"
std::string budget_text(const InnerSolveOptions& solve);

// The table for a terminal: aligned columns, strain in %, e_3D x 10^2.
std::string stability_console_table(const std::vector<StabilityRow>& rows);
// "What fails where": one line per method (finished / diverged / errors, with the cases and
// steps), Newton's unconverged steps, energy blow-ups among finished runs, the largest e_3D.
std::vector<std::string> stability_summary(const std::vector<StabilityRow>& rows,
                                           const std::vector<std::string>& methods);
// Max strain (log) and energy growth (log) per case (x: the case number, 1 = the first case),
// one series per method; diverged and failed runs marked.
PlotFigure stability_plot(const std::vector<StabilityRow>& rows, const std::vector<StabilityCase>& cases,
                          const std::vector<std::string>& methods, const std::vector<std::string>& notes);

}  // namespace fnopt
