#include <fnopt/studies/compare_study.hpp>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/rollout_file.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/metrics/step_error.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/parallel/sweep_schedule.hpp>
#include <fnopt/simulation/newton_reference.hpp>
#include <fnopt/studies/resumed_rows.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

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

const std::vector<std::string> kColumns = {"method",
                                           "N",
                                           "lr",
                                           "lr_source",
                                           "resolution",
                                           "motion",
                                           "frames",
                                           "threads",
                                           "ms_per_frame",
                                           "cpu_share",
                                           "ms_per_frame_cpu",
                                           "iterations_per_frame",
                                           "e_cd_x1e3",
                                           "e_3d_x1e2",
                                           "step_error_mean",
                                           "step_error_median",
                                           "max_strain_pct",
                                           "diverged",
                                           "frontier",
                                           "e_cd_arcsim_x1e3",
                                           "note"};

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

// One rollout's result, sent from the rank that ran it to rank 0: every field at full precision
// (the frontier is marked on the values, not the CSV's rounded text), fields separated by the
// ASCII unit separator, which no field contains.
constexpr char kSeparator = '\x1f';

std::string encode(const RunResult& r) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << r.spec.method << kSeparator << r.spec.budget << kSeparator << r.resolution << kSeparator << r.motion
    << kSeparator << r.lr_source << kSeparator << r.note;
  for (double v :
       {r.lr, r.ms, r.cpu_share, r.iterations, r.e_cd, r.e_3d, r.step_mean, r.step_median, r.strain, r.e_cd_arcsim})
    s << kSeparator << v;
  s << kSeparator << r.diverged << kSeparator << r.failed << kSeparator << r.frames << kSeparator << r.frames_requested;
  return s.str();
}

RunResult decode(const std::string& text) {
  const std::vector<std::string_view> f = split(text, kSeparator);
  if (f.size() != 20)
    throw Error("compare", "a run's result arrived damaged (" + std::to_string(f.size()) + " fields)");
  RunResult r;
  auto number = [](std::string_view v) {
    double value = NAN;
    parse_double(v, value);  // "nan" stays NAN
    return value;
  };
  r.spec.method = f[0];
  parse_int(f[1], r.spec.budget);
  r.resolution = f[2];
  r.motion = f[3];
  r.lr_source = f[4];
  r.note = f[5];
  double* fields[] = {&r.lr,   &r.ms,        &r.cpu_share,   &r.iterations, &r.e_cd,
                      &r.e_3d, &r.step_mean, &r.step_median, &r.strain,     &r.e_cd_arcsim};
  for (int i = 0; i < 10; ++i) *fields[i] = number(f[6 + i]);
  r.diverged = f[16] == "1";
  r.failed = f[17] == "1";
  parse_int(f[18], r.frames);
  parse_int(f[19], r.frames_requested);
  return r;
}

// A task of the sweep: a scene's Newton reference (run = -1) or one run on one scene.
struct Task {
  std::size_t scene = 0;
  int run = -1;
  double units = 0.0;  // estimated cost, frame-cost units (the schedule's and the progress bar's)
};

// What every run on one scene shares: the resolved scene, its reference frames, the per-step
// error bench on them (16 Newton solves by default: built once per scene and rank) and the
// ARCSim frames if there are any.
struct SceneContext {
  std::size_t scene = static_cast<std::size_t>(-1);
  std::optional<ResolvedScene> resolved;
  TrajectoryFrames reference;
  std::unique_ptr<StepErrorBench> bench;
  std::optional<TrajectoryFrames> arcsim;
};

}  // namespace

void run_compare_study(const CompareStudy& study, const Communicator& comm) {
  const std::vector<Scene>& scenes = study.scenes;
  const std::vector<RunSpec>& runs = study.runs;
  const std::vector<std::string>& methods = study.methods;
  const std::vector<double>& error_levels = study.error_levels;
  const ChamferOptions& chamfer = study.chamfer;
  const int threads = study.threads;
  const bool root = comm.is_root();
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
  auto run_label = [&](const RunSpec& run, const Scene& scene) {
    return run.method + (run.budget ? " N=" + std::to_string(run.budget) : "") + " " + resolution_text(scene) + "/" +
           motion_text(scene);
  };

  const std::string csv_path = (fs::path(study.out) / "compare.csv").string();
  // --resume: the rows of an earlier run with the same columns are kept and not run again.
  const ResumedRows resumed(csv_path, kColumns, kKeyColumns, study.resume, "compare");
  auto resumed_row = [&](std::size_t s, const RunSpec& run) {
    return resumed.find(run_key(run.method, budget_text(run), resolution_text(scenes[s]), motion_text(scenes[s])));
  };

  // The tasks: first the references still missing (every run on their scene needs them), then
  // every run not resumed. A fresh reference is also the converged Newton run of its scene (the
  // same solver, just run), so that run comes with the reference task.
  std::vector<Task> reference_tasks, run_tasks;
  std::set<std::size_t> fresh_reference_scenes;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    const Scene& scene = scenes[s];
    const int vertices = scene.rows * scene.cols;
    const bool all_resumed = std::all_of(runs.begin(), runs.end(), [&](const RunSpec& r) { return resumed_row(s, r); });
    if (!all_resumed && !fs::exists(reference_file(scene))) {
      reference_tasks.push_back({s, -1, scene.frames * cost_weight(reference_method(), 0, vertices)});
      fresh_reference_scenes.insert(s);
    }
    for (int i = 0; i < static_cast<int>(runs.size()); ++i) {
      if (resumed_row(s, runs[i])) continue;
      if (is_converged_run(runs[i]) && fresh_reference_scenes.count(s) && !study.warm_start) continue;
      run_tasks.push_back({s, i, scene.frames * cost_weight(runs[i].method, runs[i].budget, vertices)});
    }
  }
  auto costs_of = [](const std::vector<Task>& tasks) {
    std::vector<double> costs;
    for (const Task& t : tasks) costs.push_back(t.units);
    return costs;
  };
  const std::vector<int> reference_rank = schedule_largest_first(costs_of(reference_tasks), comm.size());
  const std::vector<int> run_rank = schedule_largest_first(costs_of(run_tasks), comm.size());
  // Every rank plans from the same files: none may write a reference (or a row) before all have
  // looked. A rank started late would otherwise see a reference written meanwhile, plan without
  // its task, and the ranks would wait for each other forever.
  comm.barrier();

  // Progress in frame-cost units (budget x frames), so that the ETA weighs Adam-500 over L-BFGS-10.
  double total_units = 0.0;
  for (const Task& t : reference_tasks) total_units += t.units;
  for (const Task& t : run_tasks) total_units += t.units;
  const double unit_scale = total_units > 1e9 ? 1e-3 : 1.0;
  std::optional<ProgressBar> bar;
  double done_units = 0.0;  // rank 0: every rank's finished tasks and its own running one
  if (root) {
    bar.emplace("compare", static_cast<int>(total_units * unit_scale));
    std::fprintf(stderr,
                 "fnopt compare: %zu scene%s (res %s; motions %s), %zu runs each, %d frames, %d thread%s (fixed for "
                 "every timing)%s, output %s\n",
                 scenes.size(), scenes.size() == 1 ? "" : "s", study.resolutions_text.c_str(),
                 joined(motion_names_used).c_str(), runs.size(), base.frames, threads, threads == 1 ? "" : "s",
                 comm.size() > 1 ? (", " + std::to_string(comm.size()) + " processes").c_str() : "", study.out.c_str());
    if (resumed.size() > 0)
      std::fprintf(stderr, "resuming: %zu finished runs in %s\n", resumed.size(), csv_path.c_str());
  }

  // Rank 0's view of the results: the finished runs by (scene, run), rows of compare.csv in the
  // order of a one-process run (resumed rows this run does not redo, then scene by scene, run
  // by run), however the ranks finished them.
  std::map<std::pair<std::size_t, int>, RunResult> finished;
  std::vector<RunResult> unplanned_rows;
  std::set<std::string> planned;
  for (const Scene& scene : scenes)
    for (const auto& run : runs)
      planned.insert(run_key(run.method, budget_text(run), resolution_text(scene), motion_text(scene)));
  // Rows of the earlier CSV that this run does not redo (other methods, budgets, resolutions
  // or motions) stay in it: resuming with a subset never drops finished work.
  for (const auto& row : resumed.unplanned(planned)) {
    int budget = 0;
    parse_int(row[1], budget);  // "converged" (earlier "tol1e-9"): 0, a converged run
    unplanned_rows.push_back(result_of_row({row[0], budget}, row));
  }
  auto all_results = [&] {
    std::vector<RunResult> results = unplanned_rows;
    for (std::size_t s = 0; s < scenes.size(); ++s)
      for (int i = 0; i < static_cast<int>(runs.size()); ++i) {
        if (const auto* earlier = resumed_row(s, runs[i]))
          results.push_back(result_of_row(runs[i], *earlier));
        else if (const auto it = finished.find({s, i}); it != finished.end())
          results.push_back(it->second);
      }
    mark_frontier(results, threads);
    return results;
  };
  const std::string svg_path = (fs::path(study.out) / "compare.svg").string();
  auto write_table = [&](const std::vector<RunResult>& results) {
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
  report.superres = study.preset == "superres" || (std::count(methods.begin(), methods.end(), "fnopt") > 0 &&
                                                   std::any_of(methods.begin(), methods.end(), is_interpolated_method));
  const std::size_t total_runs = runs.size() * scenes.size();
  std::set<std::size_t> reference_states;  // per-step samples of the references, as drawn
  auto write_outputs = [&](const std::vector<RunResult>& results, const std::string& status) {
    // Frames and reference states as the rows have them, which a --resume may mix.
    std::set<int> frames;
    for (const RunResult& r : results) frames.insert(r.frames_requested);
    if (frames.empty()) frames.insert(base.frames);
    std::vector<std::string> frame_texts, state_texts;
    for (int f : frames) frame_texts.push_back(std::to_string(f));
    for (std::size_t n : reference_states) state_texts.push_back(std::to_string(n));
    std::vector<std::string> notes = {
        joined(frame_texts, " or ") + " frames" + (frames.size() > 1 ? " (see each row)" : "") +
            " at dt = " + dt_text(base.dt) +
            " s; N = iterations per time step; errors vs the converged Newton rollout (residual acceleration <= 1e-4 "
            "m/s^2); " +
            "per-step error on " +
            (state_texts.empty() ? std::to_string(study.step_samples) : joined(state_texts, " or ")) +
            " reference states; e_CD with " + std::to_string(chamfer.samples) + " points per mesh",
        "motions: " + joined(motion_names_used)};
    if (!lr_notes.empty()) notes.push_back("learning rates (swept on the first scene): " + joined(lr_notes));
    write_svg(svg_path, make_compare_plot(results, methods, resolution_names, motion_names_used, threads, notes));
    report.notes = notes;
    report.status = status;
    write_compare_report(report, results);
  };

  // Rank 0 records a finished task (its own or one that arrived), rewrites the outputs and
  // prints the run's line. A message is the task's kind and index, the reference states of its
  // scene's bench, and the encoded result if the task produced a row.
  std::set<std::pair<int, std::size_t>> received;  // (phase: 0 references, 1 runs; task)
  auto record = [&](const std::string& message) {
    const auto fields = split(message, '\n');
    int phase = 0, states = 0, index = 0;
    parse_int(fields[0], phase);
    parse_int(fields[1], index);
    parse_int(fields[2], states);
    const Task& task = (phase == 0 ? reference_tasks : run_tasks)[index];
    received.insert({phase, static_cast<std::size_t>(index)});
    done_units += task.units;
    if (states > 0) reference_states.insert(states);
    // The result is the rest of the message (a note may hold line breaks).
    std::size_t body = 0;
    for (int line = 0; line < 3; ++line) body = message.find('\n', body) + 1;
    if (body >= message.size()) return;
    const RunResult r = decode(message.substr(body));
    const int run = task.run >= 0
                        ? task.run
                        : static_cast<int>(std::find_if(runs.begin(), runs.end(), is_converged_run) - runs.begin());
    finished[{task.scene, run}] = r;
    const std::vector<RunResult> results = all_results();
    write_table(results);
    write_outputs(results, "in progress, " + std::to_string(results.size() - unplanned_rows.size()) + " of " +
                               std::to_string(total_runs) + " runs done");
    const std::string label = run_label(runs[run], scenes[task.scene]);
    bar->update(static_cast<int>(done_units * unit_scale), label + " done");
    std::fprintf(stderr,
                 "%-26s %8.2f ms/frame (cpu share %.2f)  e_CD %8.3f  e_3D %8.3f  step err %9.3g  strain %6.1f%%  %s\n",
                 label.c_str(), r.ms, r.cpu_share, 1e3 * r.e_cd, 1e2 * r.e_3d, r.step_mean, 100 * r.strain,
                 r.failed ? r.note.c_str() : (r.diverged ? "DIVERGED" : "ok"));
  };
  auto take_arrived = [&] {
    Communicator::Message message;
    while (comm.take_arrived(message)) record(message.text);
  };
  auto finish_task = [&](int phase, std::size_t index, int states, const std::optional<RunResult>& result) {
    const std::string message = std::to_string(phase) + "\n" + std::to_string(index) + "\n" + std::to_string(states) +
                                "\n" + (result ? encode(*result) : std::string());
    if (root)
      record(message);
    else
      comm.send_to_root(message);
  };
  // Rank 0 waits for the other ranks' tasks of a phase.
  auto wait_for_phase = [&](int phase, const std::vector<int>& rank_of) {
    if (!root) return;
    for (std::size_t i = 0; i < rank_of.size(); ++i)
      while (!received.count({phase, i})) record(comm.wait_for().text);
  };

  auto rollout_with_progress = [&](const ResolvedScene& scene, InnerOptimizer& optimizer, const RolloutOptions& options,
                                   double units, const std::string& label) {
    const double cpu_start = process_cpu_seconds();
    const auto wall_start = std::chrono::steady_clock::now();
    TimedRollout timed;
    timed.rollout = run_rollout(scene, optimizer, options, [&](int done, int total, const StepRecord& s) {
      if (!root) return;
      take_arrived();
      char status[160];
      std::snprintf(status, sizeof status, "%s: %.1f ms/step, strain %.0f%%", label.c_str(), s.wall_ms,
                    100 * s.max_strain);
      bar->update(static_cast<int>((done_units + units * done / std::max(total, 1)) * unit_scale), status);
    });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    timed.cpu_share = wall > 0.0 ? (process_cpu_seconds() - cpu_start) / wall : NAN;
    return timed;
  };

  // The shared state of one scene's runs on this rank; tasks run scene by scene. A rank that
  // computes a reference builds the scene's context from it in memory and keeps it for its own
  // later runs there (`kept`, the reference's frames per scene until its runs come); otherwise
  // the context is built from the cached reference file.
  auto make_context = [&](std::size_t s, ResolvedScene resolved, TrajectoryFrames reference) {
    const Scene& scene = scenes[s];
    SceneContext c;
    c.scene = s;
    c.resolved.emplace(std::move(resolved));
    c.reference = std::move(reference);
    c.bench = std::make_unique<StepErrorBench>(scene, c.reference, study.step_samples);
    if (!study.arcsim_dir.empty() && scene.rows == scene.cols && scene.trajectory.empty()) {
      const std::string path =
          (fs::path(study.arcsim_dir) / ("arcsim_N" + resolution_text(scene) + "_" + motion_text(scene) + ".h5"))
              .string();
      if (fs::exists(path)) c.arcsim = read_trajectory_frames(path);
    }
    return c;
  };
  SceneContext context;
  std::map<std::size_t, SceneContext> kept;
  auto context_of = [&](std::size_t s) -> SceneContext& {
    if (context.scene == s) return context;
    if (const auto it = kept.find(s); it != kept.end()) {
      context = std::move(it->second);
      kept.erase(it);
      return context;
    }
    const Scene& scene = scenes[s];
    const std::string cache = reference_file(scene);
    if (root)
      std::fprintf(stderr, "reference %s/%s: cached %s\n", resolution_text(scene).c_str(), motion_text(scene).c_str(),
                   cache.c_str());
    context = make_context(s, resolve(scene), read_trajectory_frames(cache));
    return context;
  };

  // The measured row of one run on scene s, from its rollout.
  auto measure = [&](std::size_t s, const RunSpec& run, const OptimizerChoice& choice, InnerOptimizer& optimizer,
                     const TimedRollout& timed, RunResult& r) {
    SceneContext& c = context_of(s);
    const Scene& scene = scenes[s];
    const RolloutResult& rollout = timed.rollout;
    r.cpu_share = timed.cpu_share;
    if (study.keep_rollouts)
      write_rollout_file(
          (fs::path(study.out) / ("rollout_" + run.method + (run.budget ? "_" + std::to_string(run.budget) : "") + "_" +
                                  resolution_text(scene) + "_" + motion_text(scene) + ".h5"))
              .string(),
          rollout, to_scene_text(scene), optimizer.settings());
    r.frames = static_cast<int>(rollout.steps.size());
    r.ms = ms_per_frame(rollout);
    r.iterations = iterations_per_frame(rollout);
    r.strain = rollout.max_strain();
    r.diverged = rollout.diverged;
    if (rollout.diverged) r.note = rollout.divergence;
    const TrajectoryFrames frames = frames_of(rollout);
    // A diverged run has no error to report: over its first frames (the start is exact) it
    // would look better than every run that finished. Its error columns stay empty.
    const TrajectoryComparison comparison = compare_trajectories(c.reference, frames, -1.0, comparison_options);
    r.e_cd = rollout.diverged ? NAN : comparison.chamfer;
    r.e_3d = rollout.diverged ? NAN : comparison.e3d;
    if (c.arcsim && !rollout.diverged)
      r.e_cd_arcsim = compare_trajectories(*c.arcsim, frames, -1.0, comparison_options).chamfer;
    const auto fresh = choice.make();  // a fresh optimizer: no state from the rollout
    const StepErrorSummary steps = c.bench->evaluate(*fresh, choice.solve_options());
    r.step_mean = steps.mean;
    r.step_median = steps.median;
  };
  auto new_result = [&](std::size_t s, const RunSpec& run) {
    RunResult r;
    r.spec = run;
    r.resolution = resolution_text(scenes[s]);
    r.motion = motion_text(scenes[s]);
    r.frames_requested = scenes[s].frames;
    return r;
  };

  // 1. The Newton references still missing, each computed once, by one rank.
  std::set<std::size_t> later_scenes;  // scenes where this rank runs tasks after the references
  for (std::size_t i = 0; i < run_tasks.size(); ++i)
    if (run_rank[i] == comm.rank()) later_scenes.insert(run_tasks[i].scene);
  if (root && !run_tasks.empty()) later_scenes.insert(run_tasks.front().scene);  // the learning-rate sweep's
  const auto converged = std::find_if(runs.begin(), runs.end(), is_converged_run);
  for (std::size_t i = 0; i < reference_tasks.size(); ++i) {
    if (reference_rank[i] != comm.rank()) continue;
    const std::size_t s = reference_tasks[i].scene;
    const Scene& scene = scenes[s];
    const std::string res = resolution_text(scene), motion = motion_text(scene);
    NewtonOptimizer newton;
    RolloutOptions options;
    options.solve = reference_options;
    ResolvedScene resolved = resolve(scene);
    const TimedRollout reference =
        rollout_with_progress(resolved, newton, options, reference_tasks[i].units, "reference " + res + "/" + motion);
    write_rollout_file(reference_file(scene), reference.rollout, to_scene_text(scene), newton.settings());
    if (reference.rollout.diverged)
      std::fprintf(stderr, "warning: the Newton reference of %s/%s %s\n", res.c_str(), motion.c_str(),
                   reference.rollout.divergence.c_str());
    const bool newton_row = converged != runs.end() && !resumed_row(s, *converged) && !study.warm_start;
    const bool later = later_scenes.count(s) > 0;
    std::optional<RunResult> row;
    int states = 0;
    if (newton_row || later) {
      context = make_context(s, std::move(resolved), frames_of(reference.rollout));
      states = static_cast<int>(context.bench->steps().size());
    }
    if (newton_row) {
      row = new_result(s, *converged);
      row->note = "the reference rollout itself";
      OptimizerChoice choice = study.settings;
      choice.name = converged->method;
      choice.iterations = converged->budget;
      measure(s, *converged, choice, newton, reference, *row);
      if (row->diverged) row->note = "the reference rollout itself; " + reference.rollout.divergence;
    }
    if (later) {
      kept.emplace(s, std::move(context));
      context = SceneContext();
    }
    finish_task(0, i, states, row);
  }
  wait_for_phase(0, reference_rank);

  // 2. Learning rates: those of resumed runs, else swept once by rank 0 on the first scene
  //    that runs, per method and budget, by the mean per-step error on its reference states.
  std::map<std::string, std::vector<double>> lr_candidates = study.learning_rates;
  for (std::size_t s = 0; s < scenes.size(); ++s)
    for (const auto& run : runs)
      if (const auto* row = resumed_row(s, run);
          row && uses_learning_rate(run.method) && !chosen_lr.count({run.method, run.budget}))
        chosen_lr[{run.method, run.budget}] = {result_of_row(run, *row).lr, (*row)[3]};
  std::string lr_text;  // "method budget value source" lines, rank 0's choice for every rank
  if (root && !run_tasks.empty()) {
    const std::size_t first = run_tasks.front().scene;
    for (const auto& run : runs) {
      if (!uses_learning_rate(run.method) || chosen_lr.count({run.method, run.budget})) continue;
      const auto& candidates = lr_candidates[run.method];
      LearningRate best{candidates.front(), "given"};
      if (candidates.size() > 1) {
        SceneContext& c = context_of(first);
        const std::string res = resolution_text(scenes[first]), motion = motion_text(scenes[first]);
        double best_error = INFINITY;
        std::string tried;
        for (double lr : candidates) {
          OptimizerChoice choice = study.settings;
          choice.name = run.method;
          choice.iterations = run.budget;
          choice.learning_rate = lr;
          const auto optimizer = choice.make();
          const double error = c.bench->evaluate(*optimizer, choice.solve_options()).mean;
          tried += (tried.empty() ? "" : " ") + CsvTable::number(lr, 3) + ":" + CsvTable::number(error, 3);
          if (error < best_error) best_error = error, best.value = lr;
        }
        best.source = "swept on " + res + "/" + motion + " by mean step error";
        std::fprintf(stderr, "lr sweep %s N=%d on %s/%s (lr:mean step error) %s -> lr %g\n", run.method.c_str(),
                     run.budget, res.c_str(), motion.c_str(), tried.c_str(), best.value);
        lr_notes.push_back(run.method + " N=" + std::to_string(run.budget) + ": " + CsvTable::number(best.value, 3));
      }
      chosen_lr[{run.method, run.budget}] = best;
      std::ostringstream line;
      line << std::setprecision(17) << run.method << kSeparator << run.budget << kSeparator << best.value << kSeparator
           << best.source << '\n';
      lr_text += line.str();
    }
  }
  comm.broadcast(lr_text);
  if (!root)
    for (std::string_view line : split(lr_text, '\n')) {
      const auto f = split(line, kSeparator);
      if (f.size() != 4) continue;
      int budget = 0;
      double value = 0.0;
      parse_int(f[1], budget);
      parse_double(f[2], value);
      chosen_lr[{std::string(f[0]), budget}] = {value, std::string(f[3])};
    }

  // 3. Every run not resumed, by the rank the schedule gives it, in scene order.
  for (std::size_t i = 0; i < run_tasks.size(); ++i) {
    if (run_rank[i] != comm.rank()) continue;
    const std::size_t s = run_tasks[i].scene;
    const RunSpec& run = runs[run_tasks[i].run];
    RunResult r = new_result(s, run);
    OptimizerChoice choice = study.settings;
    choice.name = run.method;
    choice.iterations = run.budget;
    if (uses_learning_rate(run.method)) {
      const LearningRate& lr = chosen_lr[{run.method, run.budget}];
      choice.learning_rate = r.lr = lr.value;
      r.lr_source = lr.source;
    }
    SceneContext& c = context_of(s);
    try {
      const auto optimizer = choice.make();
      RolloutOptions options;
      options.solve = choice.solve_options();
      options.warm_start = study.warm_start;
      const TimedRollout timed =
          rollout_with_progress(*c.resolved, *optimizer, options, run_tasks[i].units, run_label(run, scenes[s]));
      measure(s, run, choice, *optimizer, timed, r);
    } catch (const std::exception& e) {
      r.failed = true;
      r.note = std::string("failed: ") + e.what();
    }
    finish_task(1, i, static_cast<int>(c.bench->steps().size()), r);
  }
  wait_for_phase(1, run_rank);
  if (!root) return;

  bar->finish();
  const std::vector<RunResult> results = all_results();
  const CsvTable table = write_table(results);
  write_outputs(results, "finished");
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

std::vector<RunSpec> compare_runs(const std::vector<std::string>& methods, const std::vector<int>& budgets,
                                  const std::map<std::string, std::vector<int>>& capped) {
  std::vector<RunSpec> runs;
  for (const auto& method : methods) {
    const auto given = capped.find(method);
    switch (method_traits(method).budget) {
      case BudgetKind::ToTolerance:
        runs.push_back({method, 0});
        if (given != capped.end())
          for (int budget : given->second) runs.push_back({method, budget});
        break;
      case BudgetKind::OneSolve:
        runs.push_back({method, 1});
        break;
      case BudgetKind::Iterations:
        for (int budget : given != capped.end() ? given->second : budgets) runs.push_back({method, budget});
        break;
    }
  }
  return runs;
}

}  // namespace fnopt
