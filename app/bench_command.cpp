// fnopt bench: timing tables measured in one run (docs/design.md §9): the Newton reference step at
// several resolutions, the FNO's forward/backward passes, a rollout's adjoint (§15), and the contact
// term's cost with far obstacles (§14).
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include <fnopt/adjoint/adjoint_bench.hpp>
#include <fnopt/baselines/newton.hpp>
#include <fnopt/fno/fno_bench.hpp>
#include <fnopt/fno/fno_io.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/median.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include "app/commands.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct BenchFlags {
  std::string what = "newton";
  std::string resolutions = "32,64,100";
  int frames = 390;
  int threads = 0;  // the default: set_thread_count
  bool warm_start = false;
  std::string keep;  // directory for the Newton rollouts, or empty
  std::string model;
  std::string preconditioner = "auto";
  int repeat = 1;  // newton: timed runs per resolution, in rounds
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

NewtonBenchRun time_newton_rollout(const BenchFlags& flags, const NewtonParams& params, int n, int round) {
  Scene scene;
  scene.rows = scene.cols = n;
  scene.frames = flags.frames;
  NewtonOptimizer newton(params);
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  options.warm_start = flags.warm_start;
  std::string label = "bench " + std::to_string(n) + "^2";
  if (flags.repeat > 1) label += " (" + std::to_string(round + 1) + "/" + std::to_string(flags.repeat) + ")";
  ProgressBar bar(label, scene.frames);
  const RolloutResult r =
      run_rollout(resolve(scene), newton, options, [&](int done, int, const StepRecord&) { bar.update(done); });
  bar.finish();
  if (!flags.keep.empty() && round == 0)
    write_rollout_file((std::filesystem::path(flags.keep) / ("newton_" + std::to_string(n) + ".h5")).string(), r,
                       to_scene_text(scene), newton.settings());
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

void bench_newton(const BenchFlags& flags, int threads) {
  const NewtonParams params = bench_newton_params(flags.preconditioner);
  const std::string preconditioner =
      flags.preconditioner == "auto"
          ? "P's factor, a multigrid from " + std::to_string(params.multigrid_from_dofs) + " free dofs"
          : flags.preconditioner;
  std::printf(
      "Newton reference step (residual acceleration <= %g m/s^2), corner handles, motion xy_v2, %d frames, "
      "dt = 1/60, %d thread%s, warm start %s, preconditioner %s\n",
      NewtonOptimizer::reference_solve_options().acceleration_tolerance, flags.frames, threads, threads == 1 ? "" : "s",
      flags.warm_start ? "on" : "off", preconditioner.c_str());
  if (flags.repeat > 1)
    std::printf(
        "%d runs per resolution, in rounds: ms/frame and max ms are their medians, range is ms/frame's lowest to "
        "highest\n",
        flags.repeat);
  std::printf("%6s %10s", "res", "ms/frame");
  if (flags.repeat > 1) std::printf(" %15s", "range");
  std::printf(" %10s %9s %9s %9s %10s %9s %9s %9s\n", "max ms", "iters", "max it", "builds/st", "cg it/st", "neg curv",
              "rejected", "converged");
  // Rounds over the resolutions rather than each resolution's runs back to back: a slow phase of the
  // machine then touches every resolution's runs alike (docs/design.md §9).
  const std::vector<int> resolutions = parse_resolutions(flags.resolutions);
  std::vector<std::vector<NewtonBenchRun>> runs(resolutions.size());
  for (int round = 0; round < flags.repeat; ++round)
    for (std::size_t k = 0; k < resolutions.size(); ++k) {
      runs[k].push_back(time_newton_rollout(flags, params, resolutions[k], round));
      if (round + 1 == flags.repeat) print_newton_row(resolutions[k], runs[k]);
    }
}

// The process's peak resident set so far [MB] (getrusage's ru_maxrss, in KiB on Linux).
double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

// The recorded forward pass (exact Newton steps) and the backward pass of a loss on its last frame
// (adjoint/adjoint_bench.hpp), one row per resolution; peak RSS is the process's so far, so a
// row's is at least the rows' before it.
void bench_adjoint_rows(const BenchFlags& flags, int threads) {
  std::printf(
      "adjoint of a rollout: recorded forward pass (Newton to %g m/s^2, then exact steps) and the backward pass of "
      "L = |x_last - x_rest|^2, corner handles, motion xy_v2, %d frames, dt = 1/60, %d thread%s\n",
      RecordOptions{}.acceleration_tolerance, flags.frames, threads, threads == 1 ? "" : "s");
  std::printf("%6s %12s %12s %9s %10s %10s %10s %11s %9s %s\n", "res", "fwd ms/fr", "bwd ms/fr", "bwd/fwd", "factor/st",
              "solves/st", "record MB", "peak RSS MB", "saddles", "status");
  for (int n : parse_resolutions(flags.resolutions)) {
    Scene scene;
    scene.rows = scene.cols = n;
    scene.frames = flags.frames + 1;  // --frames steps after the initial frame
    ProgressBar bar("adjoint " + std::to_string(n) + "^2", 1);
    const AdjointBenchRow row = bench_adjoint(resolve(scene));
    bar.update(1);
    bar.finish();
    const double steps = std::max(1, row.steps);
    std::printf("%4d^2 %12.1f %12.1f %9.2f %10.2f %10.2f %10.1f %11.0f %9d %s\n", n, row.forward_ms_per_frame,
                row.backward_ms_per_frame, row.backward_ms_per_frame / row.forward_ms_per_frame,
                row.factorizations / steps, row.solves / steps, row.record_bytes / 1e6, peak_rss_mb(), row.saddle_steps,
                to_string(row.status));
    std::fflush(stdout);
  }
}

// The contact term's cost where the cloth never comes near an obstacle (docs/design.md §14): the
// benchmark scene with and without two far obstacles (a floor 4 m below, a sphere 3 m behind), in
// --repeat rounds per resolution and method, the order alternating; medians, their ratio, and whether the
// two rollouts are the same (they must be: a barrier out of range adds exact zeros).
void bench_contact_rows(const BenchFlags& flags, int threads) {
  std::printf(
      "contact with far obstacles: corner handles, motion xy_v2, %d frames, dt = 1/60, %d thread%s, medians of %d "
      "alternated runs; the obstacles: floor z = -5 m, sphere centre (0.5, 3, -0.5) m radius 0.2 m\n",
      flags.frames, threads, threads == 1 ? "" : "s", flags.repeat);
  std::printf("%6s %8s %14s %14s %8s %s\n", "res", "method", "free ms/frame", "far ms/frame", "ratio", "same rollout");
  for (int n : parse_resolutions(flags.resolutions))
    for (const std::string method : {"pqn", "newton"}) {
      Scene free_scene;
      free_scene.rows = free_scene.cols = n;
      free_scene.frames = flags.frames;
      Scene far_scene = free_scene;
      apply_scene_setting(far_scene, "obstacle",
                          "plane point=0,0,-5 normal=0,0,1;sphere center=0.5,3,-0.5 radius=0.2");
      OptimizerChoice choice;
      choice.name = method;
      RolloutOptions options;
      options.solve = choice.solve_options();
      std::vector<double> free_ms, far_ms;
      bool same = true;
      ProgressBar bar("contact " + std::to_string(n) + "^2 " + method, 2 * flags.repeat);
      for (int round = 0; round < flags.repeat; ++round) {
        // The order alternates between rounds (ABBA...), so that neither run always goes second.
        const auto free_optimizer = choice.make(), far_optimizer = choice.make();
        RolloutResult free_run, far_run;
        if (round % 2 == 0) free_run = run_rollout(resolve(free_scene), *free_optimizer, options);
        far_run = run_rollout(resolve(far_scene), *far_optimizer, options);
        bar.update(2 * round + 1);
        if (round % 2 == 1) free_run = run_rollout(resolve(free_scene), *free_optimizer, options);
        bar.update(2 * round + 2);
        free_ms.push_back(free_run.mean_step_ms());
        far_ms.push_back(far_run.mean_step_ms());
        same = same && free_run.positions == far_run.positions;
      }
      bar.finish();
      const double free_median = median(free_ms), far_median = median(far_ms);
      std::printf("%4d^2 %8s %14.2f %14.2f %8.3f %s\n", n, method.c_str(), free_median, far_median,
                  far_median / free_median, same ? "yes" : "no");
      std::fflush(stdout);
    }
}

void run_bench(const BenchFlags& flags) {
  const int threads = set_thread_count(flags.threads);
  if (flags.what == "newton" || flags.what == "all") bench_newton(flags, threads);
  if (flags.what == "fno" || flags.what == "all") {
    std::ostringstream table;
    const std::string model = flags.model.empty() ? shipped_model_path() : flags.model;
    std::printf("FNO of %s\n", model.c_str());
    run_fno_bench(table, threads, load_fno_options(model), parse_resolutions(flags.resolutions));
    std::printf("%s", table.str().c_str());
  }
  if (flags.what == "adjoint") bench_adjoint_rows(flags, threads);
  if (flags.what == "contact") bench_contact_rows(flags, threads);
  if (flags.what != "newton" && flags.what != "fno" && flags.what != "adjoint" && flags.what != "contact" &&
      flags.what != "all")
    throw Error("bench", "unknown benchmark '" + flags.what + "' (choose newton, fno, adjoint, contact or all)");
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* command =
      app.add_subcommand("bench", "timing tables: the Newton step, the FNO passes, a rollout's adjoint, contact's cost");
  command
      ->add_option("what", flags->what,
                   "newton, fno, adjoint (a recorded rollout's forward and backward passes), contact (the benchmark "
                   "scene with and without far obstacles, pqn and newton) or all (newton and fno)")
      ->capture_default_str();
  command->add_option("--res", flags->resolutions, "resolutions, comma-separated")->capture_default_str();
  command->add_option("--model", flags->model, "fno: the model whose shape is timed (default: the shipped model)");
  command->add_option("--frames", flags->frames, "frames per resolution (newton, adjoint, contact)")
      ->capture_default_str();
  add_threads_flag(*command, flags->threads);
  command
      ->add_option(
          "--keep", flags->keep,
          "newton: also write each rollout to DIR/newton_<res>.h5 (an existing directory; with --repeat, the first "
          "run's)")
      ->check(CLI::ExistingDirectory);
  command->add_flag("--warm-start", flags->warm_start, "start each step from the previous acceleration");
  command
      ->add_option("--repeat", flags->repeat,
                   "newton, contact: time each resolution this many times, in rounds; the table gives the medians "
                   "(newton: and ms/frame's range)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  command
      ->add_option("--preconditioner", flags->preconditioner,
                   "newton: CG's preconditioner: auto (P's Cholesky factor, on fine grids a multigrid V-cycle), "
                   "factor or multigrid at every grid")
      ->capture_default_str();
  command->callback([flags] { run_bench(*flags); });
});

}  // namespace
}  // namespace fnopt::app
