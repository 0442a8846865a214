#include "studies/compare_study.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>

#include "baselines/newton.hpp"
#include "io/csv_table.hpp"
#include "io/rollout_file.hpp"
#include "io/svg_plot.hpp"
#include "metrics/step_error.hpp"
#include "metrics/trajectory_error.hpp"
#include "studies/newton_reference.hpp"
#include "studies/resumed_rows.hpp"
#include "util/error.hpp"
#include "util/parse_text.hpp"
#include "util/progress_bar.hpp"

namespace fnopt {

namespace fs = std::filesystem;

std::string resolution_text(const Scene& scene) {
  return scene.rows == scene.cols ? std::to_string(scene.rows)
                                  : std::to_string(scene.rows) + "x" + std::to_string(scene.cols);
}

std::string motion_text(const Scene& scene) {
  return scene.trajectory.empty() ? scene.motion : fs::path(scene.trajectory).filename().string();
}

namespace {

bool uses_learning_rate(const std::string& method) { return method_traits(method).learning_rate; }

double iterations_per_frame(const RolloutResult& rollout) {
  return rollout.steps.empty() ? std::nan("") : static_cast<double>(rollout.total_iterations()) / rollout.steps.size();
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

// A rollout and the share of a core the process got while it ran (CPU time / wall time).
struct TimedRollout {
  RolloutResult rollout;
  double cpu_share = NAN;
};

// Relative cost of one frame of a run (methods/registry.hpp), for the progress bar's ETA.
double cost_weight(const std::string& method, int budget, int vertices) {
  return 1000.0 * frame_cost(method, budget, is_converged_run({method, budget}), vertices);  // whole units
}

struct LearningRate {
  double value = 0.0;
  std::string source;
};

// compare.csv's rows are keyed by method, N, resolution and motion (ResumedRows).
const std::vector<std::string> kKeyColumns = {"method", "N", "resolution", "motion"};

std::string run_key(const std::string& method, const std::string& budget, const std::string& res,
                    const std::string& motion) {
  return ResumedRows::key({method, budget, res, motion});
}

const std::vector<std::string> kColumns = {
    "method", "N", "lr", "lr_source", "resolution", "motion", "frames", "threads", "ms_per_frame",
    "cpu_share", "ms_per_frame_cpu", "iterations_per_frame", "e_cd_x1e3", "e_3d_x1e2", "step_error_mean", "step_error_median", "max_strain_pct",
    "diverged", "frontier", "e_cd_arcsim_x1e3", "note"};

std::vector<std::string> csv_row(const RunResult& r, int threads) {
  // Undefined values (a diverged run's errors) are empty cells, not "nan".
  auto num = [](double v, int digits = 4) { return std::isnan(v) ? std::string() : CsvTable::number(v, digits); };
  return {r.spec.method,
          budget_text(r.spec),
          uses_learning_rate(r.spec.method) ? num(r.lr) : "",
          r.lr_source,
          r.resolution,
          r.motion,
          std::to_string(r.frames) + "/" + std::to_string(r.frames_requested),
          std::to_string(threads),
          num(r.ms),
          num(r.cpu_share, 3),
          num(r.ms * std::min(1.0, r.cpu_share)),
          num(r.iterations),
          num(1e3 * r.e_cd),
          num(1e2 * r.e_3d),
          num(r.step_mean),
          num(r.step_median),
          num(100.0 * r.strain),
          r.failed ? "error" : (r.diverged ? "yes" : "no"),
          r.frontier ? "yes" : "no",
          std::isnan(r.e_cd_arcsim) ? "" : num(1e3 * r.e_cd_arcsim),
          r.note};
}

// A row of an earlier compare.csv back into a result (--resume).
RunResult result_of_row(const RunSpec& spec, const std::vector<std::string>& row) {
  auto cell = [&](const std::string& column) {
    const auto at = std::find(kColumns.begin(), kColumns.end(), column) - kColumns.begin();
    return row[at];
  };
  auto num = [&](const std::string& column) {
    double value = NAN;
    return parse_double(cell(column), value) ? value : NAN;
  };
  RunResult r;
  r.spec = spec;
  r.resolution = cell("resolution");
  r.motion = cell("motion");
  r.lr = num("lr");
  r.lr_source = cell("lr_source");
  r.ms = num("ms_per_frame");
  r.cpu_share = num("cpu_share");
  r.iterations = num("iterations_per_frame");
  r.e_cd = 1e-3 * num("e_cd_x1e3");
  r.e_3d = 1e-2 * num("e_3d_x1e2");
  r.step_mean = num("step_error_mean");
  r.step_median = num("step_error_median");
  r.strain = 1e-2 * num("max_strain_pct");
  r.e_cd_arcsim = 1e-3 * num("e_cd_arcsim_x1e3");
  r.diverged = cell("diverged") == "yes";
  r.failed = cell("diverged") == "error";
  const auto frames = split(cell("frames"), '/');
  if (frames.size() == 2) parse_int(frames[0], r.frames), parse_int(frames[1], r.frames_requested);
  r.note = cell("note");
  return r;
}


}  // namespace

void run_compare_study(const CompareStudy& study) {
  const std::vector<Scene>& scenes = study.scenes;
  const std::vector<RunSpec>& runs = study.runs;
  const std::vector<std::string>& methods = study.methods;
  const std::vector<double>& error_levels = study.error_levels;
  std::map<std::string, std::vector<double>> lr_candidates = study.learning_rates;
  const ChamferOptions& chamfer = study.chamfer;
  const int threads = study.threads;
  const Scene& base = scenes.front();
  std::vector<std::string> resolution_names, motion_names_used;
  for (const auto& scene : scenes) {
    if (std::find(resolution_names.begin(), resolution_names.end(), resolution_text(scene)) == resolution_names.end())
      resolution_names.push_back(resolution_text(scene));
    if (std::find(motion_names_used.begin(), motion_names_used.end(), motion_text(scene)) == motion_names_used.end())
      motion_names_used.push_back(motion_text(scene));
  }
  const InnerSolveOptions reference_options = NewtonOptimizer::reference_solve_options();
  auto reference_file = [&](const Scene& scene) {
    return newton_reference_path(study.out, resolution_text(scene) + "_" + motion_text(scene), scene);
  };

  // Progress in frame-cost units (budget x frames), so that the ETA weighs Adam-500 over L-BFGS-10.
  long long total_units = 0;
  for (const auto& scene : scenes) {
    if (!fs::exists(reference_file(scene))) total_units += static_cast<long long>(scene.frames * cost_weight("newton", 0, scene.rows * scene.cols));
    for (const auto& run : runs) total_units += static_cast<long long>(scene.frames * cost_weight(run.method, run.budget, scene.rows * scene.cols));
  }
  const double unit_scale = total_units > 1'000'000'000LL ? 1e-3 : 1.0;
  ProgressBar bar("compare", static_cast<int>(total_units * unit_scale));
  long long done_units = 0;

  std::fprintf(stderr,
               "fnopt compare: %zu scene%s (res %s; motions %s), %zu runs each, %d frames, %d thread%s (fixed for "
               "every timing), output %s\n",
               scenes.size(), scenes.size() == 1 ? "" : "s", study.resolutions_text.c_str(),
               joined(motion_names_used).c_str(), runs.size(), base.frames, threads, threads == 1 ? "" : "s",
               study.out.c_str());

  std::vector<RunResult> results;  // every row of compare.csv, in its order
  const std::string csv_path = (fs::path(study.out) / "compare.csv").string();
  // --resume: the rows of an earlier run with the same columns are kept and not run again.
  const ResumedRows resumed(csv_path, kColumns, kKeyColumns, study.resume, "compare");
  if (resumed.size() > 0) std::fprintf(stderr, "resuming: %zu finished runs in %s\n", resumed.size(), csv_path.c_str());
  // Rows of the earlier CSV that this run does not redo (other methods, budgets, resolutions
  // or motions) stay in it: resuming with a subset never drops finished work.
  std::set<std::string> planned;
  for (const Scene& scene : scenes)
    for (const auto& run : runs) planned.insert(run_key(run.method, budget_text(run), resolution_text(scene), motion_text(scene)));
  for (const auto& row : resumed.unplanned(planned)) {
    int budget = 0;
    parse_int(row[1], budget);  // "tol1e-9": 0, a converged run
    results.push_back(result_of_row({row[0], budget}, row));
  }
  const std::string svg_path = (fs::path(study.out) / "compare.svg").string();
  // compare.csv from `results`, the frontier marked anew over every row.
  auto write_table = [&] {
    mark_frontier(results, threads);
    CsvTable table(kColumns);
    for (const RunResult& r : results) table.add_row(csv_row(r, threads));
    table.write(csv_path);
    return table;
  };
  std::map<std::pair<std::string, int>, LearningRate> chosen_lr;
  std::vector<std::string> lr_notes;
  TrajectoryComparisonOptions comparison_options;
  comparison_options.chamfer = chamfer;
  comparison_options.chamfer_stride = study.cd_stride;

  // compare.svg and report.md (and superres.svg), rewritten after every run.
  CompareReport report;
  report.directory = study.out;
  report.command_line = study.command_line;
  report.scene_text = to_scene_text(scenes.front());
  report.resolutions = resolution_names;
  report.motions = motion_names_used;
  report.methods = methods;
  report.threads = threads;
  report.preset = study.preset;
  report.error_levels = error_levels;
  report.superres = study.preset == "superres" ||
                    (std::count(methods.begin(), methods.end(), "fnopt") > 0 &&
                     std::any_of(methods.begin(), methods.end(), is_interpolated_method));
  const std::size_t total_runs = runs.size() * scenes.size();
  std::set<std::size_t> reference_states;  // per-step samples of the references, as drawn
  auto write_outputs = [&](const std::string& status) {
    // Frames and reference states as the rows have them, which a --resume may mix.
    std::set<int> frames;
    for (const RunResult& r : results) frames.insert(r.frames_requested);
    if (frames.empty()) frames.insert(base.frames);
    std::vector<std::string> frame_texts, state_texts;
    for (int f : frames) frame_texts.push_back(std::to_string(f));
    for (std::size_t n : reference_states) state_texts.push_back(std::to_string(n));
    std::vector<std::string> notes = {
        joined(frame_texts, " or ") + " frames" + (frames.size() > 1 ? " (see each row)" : "") + " at dt = " +
            dt_text(base.dt) + " s; N = iterations per time step; errors vs a Newton rollout converged to 1e-9; " +
            "per-step error on " + (state_texts.empty() ? std::to_string(study.step_samples) : joined(state_texts, " or ")) +
            " reference states; e_CD with " + std::to_string(chamfer.samples) + " points per mesh",
        "motions: " + joined(motion_names_used)};
    if (!lr_notes.empty()) notes.push_back("learning rates (swept on the first scene): " + joined(lr_notes));
    write_svg(svg_path, make_compare_plot(results, methods, resolution_names, motion_names_used, threads, notes));
    report.notes = notes;
    report.status = status;
    write_compare_report(report, results);
  };

  auto rollout_with_progress = [&](const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options,
                                   double weight, const std::string& label) {
    const long long start_units = done_units;
    const double cpu_start = process_cpu_seconds();
    const auto wall_start = std::chrono::steady_clock::now();
    TimedRollout timed;
    timed.rollout = run_rollout(scene, optimizer, options, [&](int done, int, const StepRecord& s) {
      char status[160];
      std::snprintf(status, sizeof status, "%s: %.1f ms/step, strain %.0f%%", label.c_str(), s.wall_ms,
                    100 * s.max_strain);
      bar.update(static_cast<int>((start_units + static_cast<long long>(done * weight)) * unit_scale), status);
    });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    timed.cpu_share = wall > 0.0 ? (process_cpu_seconds() - cpu_start) / wall : NAN;
    done_units = start_units + static_cast<long long>(scene.scene.frames * weight);
    return timed;
  };

  for (const Scene& scene : scenes) {
    const ResolvedScene resolved = resolve(scene);  // once, for the reference and every run
    const std::string res = resolution_text(scene), motion = motion_text(scene);
    for (const auto& run : runs) {  // learning rates of resumed runs
      const auto* row = resumed.find(run_key(run.method, budget_text(run), res, motion));
      if (row && uses_learning_rate(run.method) && !chosen_lr.count({run.method, run.budget}))
        chosen_lr[{run.method, run.budget}] = {result_of_row(run, *row).lr, (*row)[3]};
    }
    const bool all_resumed = std::all_of(runs.begin(), runs.end(), [&](const RunSpec& run) {
      return resumed.find(run_key(run.method, budget_text(run), res, motion)) != nullptr;
    });
    // 1. The Newton reference: cached, or computed now (and then also used as the newton run).
    const std::string cache = reference_file(scene);
    std::optional<TimedRollout> fresh_reference;
    TrajectoryFrames reference;
    std::unique_ptr<StepErrorBench> bench_storage;
    if (!all_resumed) {
      if (fs::exists(cache)) {
        reference = read_trajectory_frames(cache);
        std::fprintf(stderr, "reference %s/%s: cached %s\n", res.c_str(), motion.c_str(), cache.c_str());
      } else {
        NewtonOptimizer newton;
        RolloutOptions options;
        options.solve = reference_options;
        fresh_reference = rollout_with_progress(resolved, newton, options, cost_weight("newton", 0, scene.rows * scene.cols),
                                                "reference " + res + "/" + motion);
        write_rollout_file(cache, fresh_reference->rollout, to_scene_text(scene), newton.settings());
        reference = frames_of(fresh_reference->rollout);
        if (fresh_reference->rollout.diverged)
          std::fprintf(stderr, "warning: the Newton reference of %s/%s %s\n", res.c_str(), motion.c_str(),
                       fresh_reference->rollout.divergence.c_str());
      }
      bench_storage = std::make_unique<StepErrorBench>(scene, reference, study.step_samples);
      reference_states.insert(bench_storage->steps().size());
    } else if (!fs::exists(cache)) {
      done_units += static_cast<long long>(scene.frames * cost_weight("newton", 0, scene.rows * scene.cols));
    }
    StepErrorBench* bench = bench_storage.get();

    std::optional<TrajectoryFrames> arcsim;
    std::string arcsim_path;
    if (!all_resumed && !study.arcsim_dir.empty() && scene.rows == scene.cols && scene.trajectory.empty()) {
      arcsim_path = (fs::path(study.arcsim_dir) / ("arcsim_N" + res + "_" + motion + ".h5")).string();
      if (fs::exists(arcsim_path)) arcsim = read_trajectory_frames(arcsim_path);
    }

    // 2. Learning rates: swept once, on the first scene, per method and budget, by the mean
    //    per-step error on that scene's reference states.
    for (const auto& run : runs) {
      if (!uses_learning_rate(run.method) || chosen_lr.count({run.method, run.budget}) || !bench) continue;
      const auto& candidates = lr_candidates[run.method];
      LearningRate best{candidates.front(), "given"};
      if (candidates.size() > 1) {
        double best_error = INFINITY;
        std::string tried;
        for (double lr : candidates) {
          OptimizerChoice choice = study.settings;
          choice.name = run.method;
          choice.iterations = run.budget;
          choice.learning_rate = lr;
          const auto optimizer = choice.make();
          const double error = bench->evaluate(*optimizer, choice.solve_options()).mean;
          tried += (tried.empty() ? "" : " ") + CsvTable::number(lr, 3) + ":" + CsvTable::number(error, 3);
          if (error < best_error) best_error = error, best.value = lr;
        }
        best.source = "swept on " + res + "/" + motion + " by mean step error";
        std::fprintf(stderr, "lr sweep %s N=%d on %s/%s (lr:mean step error) %s -> lr %g\n", run.method.c_str(),
                     run.budget, res.c_str(), motion.c_str(), tried.c_str(), best.value);
        lr_notes.push_back(run.method + " N=" + std::to_string(run.budget) + ": " + CsvTable::number(best.value, 3));
      }
      chosen_lr[{run.method, run.budget}] = best;
    }

    // 3. Every optimizer and budget.
    for (const auto& run : runs) {
      const std::string label = run.method + (run.budget ? " N=" + std::to_string(run.budget) : "") + " " + res +
                                "/" + motion;
      const double weight = cost_weight(run.method, run.budget, scene.rows * scene.cols);
      if (const auto* earlier = resumed.find(run_key(run.method, budget_text(run), res, motion))) {
        results.push_back(result_of_row(run, *earlier));
        done_units += static_cast<long long>(scene.frames * weight);
        std::fprintf(stderr, "%-26s resumed from %s\n", label.c_str(), csv_path.c_str());
        continue;
      }
      RunResult r;
      r.spec = run;
      r.resolution = res;
      r.motion = motion;
      r.frames_requested = scene.frames;
      OptimizerChoice choice = study.settings;
      choice.name = run.method;
      choice.iterations = run.budget;
      if (uses_learning_rate(run.method)) {
        const LearningRate& lr = chosen_lr[{run.method, run.budget}];
        choice.learning_rate = r.lr = lr.value;
        r.lr_source = lr.source;
      }
      try {
        const auto optimizer = choice.make();
        RolloutOptions options;
        options.solve = choice.solve_options();
        options.warm_start = study.warm_start;
        TimedRollout timed;
        if (is_converged_run(run) && fresh_reference && !study.warm_start) {
          timed = *fresh_reference;  // the same solver, just run: reuse it (its timing included)
          done_units += static_cast<long long>(scene.frames * weight);
          r.note = "the reference rollout itself";
        } else {
          timed = rollout_with_progress(resolved, *optimizer, options, weight, label);
        }
        const RolloutResult& rollout = timed.rollout;
        r.cpu_share = timed.cpu_share;
        if (study.keep_rollouts)
          write_rollout_file((fs::path(study.out) / ("rollout_" + run.method +
                                                     (run.budget ? "_" + std::to_string(run.budget) : "") + "_" +
                                                     res + "_" + motion + ".h5"))
                                 .string(),
                             rollout, to_scene_text(scene), optimizer->settings());
        r.frames = static_cast<int>(rollout.steps.size());
        r.ms = ms_per_frame(rollout);
        r.iterations = iterations_per_frame(rollout);
        r.strain = rollout.max_strain();
        r.diverged = rollout.diverged;
        if (rollout.diverged) r.note = rollout.divergence;
        const TrajectoryFrames frames = frames_of(rollout);
        // A diverged run has no error to report: over its first frames (the start is exact) it
        // would look better than every run that finished. Its error columns stay empty.
        const TrajectoryComparison c = compare_trajectories(reference, frames, -1.0, comparison_options);
        r.e_cd = rollout.diverged ? NAN : c.chamfer;
        r.e_3d = rollout.diverged ? NAN : c.e3d;
        if (arcsim && !rollout.diverged) {
          TrajectoryComparisonOptions o = comparison_options;
          r.e_cd_arcsim = compare_trajectories(*arcsim, frames, -1.0, o).chamfer;
        }
        const auto fresh = choice.make();  // a fresh optimizer: no state from the rollout
        const StepErrorSummary steps = bench->evaluate(*fresh, choice.solve_options());
        r.step_mean = steps.mean;
        r.step_median = steps.median;
      } catch (const std::exception& e) {
        r.failed = true;
        r.note = std::string("failed: ") + e.what();
        done_units += static_cast<long long>(scene.frames * weight);
      }
      results.push_back(r);
      write_table();
      write_outputs("in progress, " + std::to_string(results.size()) + " of " + std::to_string(total_runs) +
                    " runs done");
      bar.update(static_cast<int>(done_units * unit_scale), label + " done");
      std::fprintf(stderr, "%-26s %8.2f ms/frame (cpu share %.2f)  e_CD %8.3f  e_3D %8.3f  step err %9.3g  strain %6.1f%%  %s\n",
                   label.c_str(), r.ms, r.cpu_share, 1e3 * r.e_cd, 1e2 * r.e_3d, r.step_mean, 100 * r.strain,
                   r.failed ? r.note.c_str() : (r.diverged ? "DIVERGED" : "ok"));
    }
  }
  bar.finish();
  const CsvTable table = write_table();  // with the rows resumed after the last computed one
  write_outputs("finished");
  std::printf("%s", table.text().c_str());
  for (const std::string& res : resolution_names) {
    std::printf("fastest at %s (mean over the motions, runs that diverged nowhere):", resolution_title(res).c_str());
    for (const LevelWinner& w : fastest_within(results, res, error_levels, threads))
      std::printf("  e_CD x10^3 <= %g: %s", 1e3 * w.level,
                  w.method.empty() ? "none"
                                   : (w.method + " N=" + std::to_string(w.budget) + " (" + CsvTable::number(w.ms, 3) +
                                      " ms/frame, " + CsvTable::number(1e3 * w.e_cd, 3) + ")")
                                         .c_str());
    std::printf("\n");
  }
  std::printf("wrote %s, %s and %s (%d thread%s)\n", csv_path.c_str(), svg_path.c_str(),
              (fs::path(study.out) / "report.md").string().c_str(), threads, threads == 1 ? "" : "s");
}

}  // namespace fnopt
