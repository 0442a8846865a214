#pragma once
// `fnopt compare`'s study (docs/design.md §8): every inner optimizer on the same scenes, error
// against run time. Per scene (resolution x motion): a Newton reference rollout (cached in the
// output directory, simulation/newton_reference.hpp), then one rollout per optimizer and iteration
// budget, each measured the same way: ms/frame after warm-up at a fixed thread count, e_CD x 10^3
// and e_3D x 10^2 against the reference, the mean per-step optimisation error on sampled
// reference states, max edge strain, divergence; optionally e_CD against ARCSim. Writes
// DIR/compare.csv (one row per run, rewritten after every run, with the frontier column),
// DIR/compare.svg and DIR/report.md.
#include <map>
#include <string>
#include <vector>

#include <fnopt/methods/registry.hpp>
#include <fnopt/metrics/chamfer.hpp>
#include <fnopt/parallel/communicator.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/studies/compare/compare_report.hpp>

namespace fnopt {

// A grid of the study: rows x cols vertices.
struct GridSize {
  int rows = 0, cols = 0;
};

// The scenes of every resolution and motion on `base` (resolution by resolution); a base with a
// trajectory file runs that instead of the motions, once per resolution.
std::vector<Scene> compare_scenes(const Scene& base, const std::vector<GridSize>& resolutions,
                                  const std::vector<std::string>& motions);

struct CompareStudy {
  std::vector<Scene> scenes;         // resolution x motion
  std::vector<std::string> methods;  // in the order given
  std::vector<int> budgets = {10};   // iteration budgets of every method that takes one
  // Budgets of single methods, in place of `budgets` (newton=1,2,3: Newton also capped).
  std::map<std::string, std::vector<int>> budgets_for;
  OptimizerChoice settings;  // --model and the other per-method settings of every run
  // Learning-rate candidates of the methods that take one; several are swept on the first scene
  // by the mean per-step error, per method and budget.
  std::map<std::string, std::vector<double>> learning_rates = {{"gd", {0.25, 0.5, 1, 1.5, 1.9}},
                                                               {"adam", {0.0003, 0.001, 0.003, 0.01}}};
  std::string out;                                            // the output directory (made and checked writable)
  std::string arcsim_dir;                                     // "" for none
  // The reference every error is measured against: "newton" (the registry's reference), or
  // "newton-min", which leaves saddles and ends at minima (docs/design.md §6): the reference off
  // the corner presets, where Newton's step can end at a saddle.
  std::string reference = "newton";
  std::string preset;                                         // "superres" or ""
  std::string resolutions_text;                               // as given, for the banner
  std::string command_line;                                   // for report.md
  std::vector<double> error_levels = {1e-3, 0.3e-3, 0.1e-3};  // e_CD levels of the "fastest within" lines
  ChamferOptions chamfer;
  int cd_stride = 2;      // e_CD on every k-th matched frame (2: every 1/30 s at dt = 1/60)
  int step_samples = 16;  // reference states of the per-step error
  int threads = 1;        // in effect (set by the caller), printed with every timing
  bool warm_start = false;
  bool keep_rollouts = false;
  bool resume = false;

  // Every check a request must pass before any work: the scenes valid, every method known and
  // fitting every grid, positive budgets, samples, strides, levels and learning rates. Throws
  // Error("compare.<field>", ...) (Error("optimizer", ...) for a method, the scene's own for a
  // scene, Error("cd-samples", ...) for the chamfer samples).
  void validate() const;
  // Every method at its budgets (compare_runs), in the order run and written.
  std::vector<RunSpec> runs() const;
};

// With more than one process (mpirun, srun), the references still missing and then the runs are
// spread over the ranks largest first (parallel/sweep_schedule.hpp), each computed once; rank 0
// gathers the results and writes the outputs exactly as one process would (the same rows in
// the same order), after every run that finishes anywhere. DIR must be one shared folder.
void run_compare_study(const CompareStudy& study, const Communicator& comm = Communicator::world());

// The runs of `methods`: a method that runs to its tolerance runs so, and also capped at the
// budgets `capped` gives it (newton=1,2,3: Newton stopped after that many iterations); a
// one-solve method runs once; every other method at `budgets`, or at capped's where it has some.
std::vector<RunSpec> compare_runs(const std::vector<std::string>& methods, const std::vector<int>& budgets,
                                  const std::map<std::string, std::vector<int>>& capped = {});

// "32" (32 x 32) or "32x64" (rows x columns): a scene's resolution as compare writes it.
std::string resolution_text(const Scene& scene);
// The motion's name, or the trajectory file's name.
std::string motion_text(const Scene& scene);

}  // namespace fnopt
