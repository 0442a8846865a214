#include <fnopt/studies/bench/bench_newton.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/median.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

// The reference's parameters with CG's preconditioner as --preconditioner asks: auto (the
// reference's own choice by grid size), factor or multigrid at every grid.
NewtonParams bench_newton_params(const std::string& preconditioner) {
  NewtonParams params;
  if (preconditioner == "factor")
    params.multigrid_from_dofs = std::numeric_limits<int>::max();
  else if (preconditioner == "multigrid")
    params.multigrid_from_dofs = 0;
  else if (preconditioner != "auto")
    throw Error("preconditioner", "expected auto, factor or multigrid, got '" + preconditioner + "'");
  return params;
}

// One timed Newton rollout: its times and the solver's work.
struct NewtonBenchRun {
  double ms_per_frame = 0.0, max_ms = 0.0;
  int steps = 0, iterations = 0, max_iterations = 0, converged = 0;
  NewtonCounters counters;

  bool same_work(const NewtonBenchRun& other) const {
    return iterations == other.iterations && counters.cg_iterations == other.counters.cg_iterations &&
           counters.factorizations == other.counters.factorizations &&
           counters.rejected_trials == other.counters.rejected_trials;
  }
};

NewtonBenchRun time_newton_rollout(const BenchRun& bench, const NewtonParams& params, int n, int round) {
  Scene scene;
  scene.rows = scene.cols = n;
  scene.frames = bench.frames;
  NewtonOptimizer newton(params);
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  options.warm_start = bench.warm_start;
  std::string label = "bench " + std::to_string(n) + "^2";
  if (bench.repeat > 1) label += " (" + std::to_string(round + 1) + "/" + std::to_string(bench.repeat) + ")";
  ProgressBar bar(label, scene.frames);
  const RolloutResult r =
      run_rollout(resolve(scene), newton, options, [&](int done, int, const StepRecord&) { bar.update(done); });
  bar.finish();
  if (!bench.keep.empty() && round == 0)
    write_rollout_file((std::filesystem::path(bench.keep) / ("newton_" + std::to_string(n) + ".h5")).string(), r, scene,
                       newton.settings());
  NewtonBenchRun run;
  run.ms_per_frame = r.mean_step_ms();
  run.steps = static_cast<int>(r.steps.size());
  run.iterations = r.total_iterations();
  run.converged = r.converged_steps();
  run.counters = newton.counters();
  for (const auto& s : r.steps) {
    run.max_iterations = std::max(run.max_iterations, s.iterations);
    run.max_ms = std::max(run.max_ms, s.wall_ms);
  }
  return run;
}

// A resolution's row: with several runs, the medians of ms/frame and max ms and ms/frame's range; the
// work counts are the first run's (on one thread every run does the same work, and the row says so where not).
void print_newton_row(int n, const std::vector<NewtonBenchRun>& runs) {
  std::vector<double> ms, max_ms;
  for (const NewtonBenchRun& run : runs) {
    ms.push_back(run.ms_per_frame);
    max_ms.push_back(run.max_ms);
  }
  const NewtonBenchRun& first = runs.front();
  const double steps = first.steps;
  const auto& c = first.counters;
  const double iterations = std::max(1, first.iterations);
  std::printf("%4d^2 %10.1f", n, median(ms));
  if (runs.size() > 1) {
    const auto [low, high] = std::minmax_element(ms.begin(), ms.end());
    char range[64];
    std::snprintf(range, sizeof range, "%.1f-%.1f", *low, *high);
    std::printf(" %15s", range);
  }
  std::printf(" %10.1f %9.2f %9d %9.2f %10.2f %8.1f%% %9.2f %5d/%d\n", median(max_ms), first.iterations / steps,
              first.max_iterations, c.factorizations / steps, c.cg_iterations / steps,
              100.0 * c.negative_curvature / iterations, c.rejected_trials / steps, first.converged, first.steps);
  if (std::any_of(runs.begin(), runs.end(), [&](const NewtonBenchRun& run) { return !run.same_work(first); }))
    std::printf("       (the runs did different work; the counts are the first run's)\n");
  if (c.multigrid_fallbacks > 0)
    std::printf("       (the multigrid gave way to P's factor: a fresh V-cycle left CG at its cap)\n");
  std::fflush(stdout);
}

}  // namespace

void bench_newton_table(const BenchRun& run) {
  const int threads = run.threads;
  const NewtonParams params = bench_newton_params(run.preconditioner);
  const std::string preconditioner =
      run.preconditioner == "auto"
          ? "P's factor, a multigrid from " + std::to_string(params.multigrid_from_dofs) + " free dofs"
          : run.preconditioner;
  std::printf(
      "Newton reference step (residual acceleration <= %g m/s^2), corner handles, motion xy_v2, %d frames, "
      "dt = 1/60, %d thread%s, warm start %s, preconditioner %s\n",
      NewtonOptimizer::reference_solve_options().acceleration_tolerance, run.frames, threads, threads == 1 ? "" : "s",
      run.warm_start ? "on" : "off", preconditioner.c_str());
  if (run.repeat > 1)
    std::printf(
        "%d runs per resolution, in rounds: ms/frame and max ms are their medians, range is ms/frame's lowest to "
        "highest\n",
        run.repeat);
  std::printf("%6s %10s", "res", "ms/frame");
  if (run.repeat > 1) std::printf(" %15s", "range");
  std::printf(" %10s %9s %9s %9s %10s %9s %9s %9s\n", "max ms", "iters", "max it", "builds/st", "cg it/st", "neg curv",
              "rejected", "converged");
  // Rounds over the resolutions rather than each resolution's runs back to back: a slow phase of the
  // machine then touches every resolution's runs alike (docs/design.md §9).
  const std::vector<int> resolutions = run.resolutions;
  std::vector<std::vector<NewtonBenchRun>> runs(resolutions.size());
  for (int round = 0; round < run.repeat; ++round)
    for (std::size_t k = 0; k < resolutions.size(); ++k) {
      runs[k].push_back(time_newton_rollout(run, params, resolutions[k], round));
      if (round + 1 == run.repeat) print_newton_row(resolutions[k], runs[k]);
    }
}


}  // namespace fnopt
