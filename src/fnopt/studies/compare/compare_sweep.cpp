#include <fnopt/studies/compare/compare_sweep.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/simulation/newton_reference.hpp>
#include <fnopt/studies/compare/compare_rows.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace fs = std::filesystem;

namespace {

template <class T>
void add_once(std::vector<T>& list, const T& value) {
  if (std::find(list.begin(), list.end(), value) == list.end()) list.push_back(value);
}

}  // namespace

CompareSweep::CompareSweep(const CompareStudy& study, const Communicator& comm)
    : study_(study),
      comm_(comm),
      runs_(study.runs()),
      csv_path_((fs::path(study.out) / "compare.csv").string()),
      svg_path_((fs::path(study.out) / "compare.svg").string()),
      resumed_(csv_path_, compare_columns(), compare_key_columns(), study.resume, "compare"),
      rows_(resumed_) {
  for (const Scene& scene : study.scenes) {
    add_once(resolutions_, resolution_text(scene));
    add_once(motions_, motion_text(scene));
    for (const RunSpec& run : runs_)
      rows_.plan({run.method, budget_text(run), resolution_text(scene), motion_text(scene)});
  }
  for (const auto& row : rows_.unplanned()) {
    int budget = 0;
    parse_int(row[1], budget);  // "converged" (earlier "tol1e-9"): 0, a converged run
    unplanned_.push_back(run_result_of_row({row[0], budget}, row));
  }
  report_ = make_report();
}

void CompareSweep::run_study() {
  runner_.emplace("compare", plan(), comm_);
  for (std::size_t t = 0; t < tasks_.size(); ++t)
    if (tasks_[t].run >= 0 && runner_->ranks()[t] == comm_.rank()) later_scenes_.insert(tasks_[t].scene);
  const auto first_run = std::find_if(tasks_.begin(), tasks_.end(), [](const Task& t) { return t.run >= 0; });
  if (comm_.is_root() && first_run != tasks_.end()) later_scenes_.insert(first_run->scene);  // the lr sweep's
  if (comm_.is_root()) print_banner();

  runner_->run_phase(0, *this);
  choose_learning_rates();
  runner_->run_phase(1, *this);
  if (!comm_.is_root()) return;
  runner_->finish();
  const std::vector<RunResult> results = all_results();
  const CsvTable table = write_table(results);
  write_outputs(results, "finished");
  print_summary(results, table);
}

// The tasks: first the references still missing (every run on their scene needs them), then
// every run not resumed. A fresh reference is also the converged Newton run of its scene (the
// same solver, just run), so that run comes with the reference task.
std::vector<SweepTask> CompareSweep::plan() {
  std::vector<SweepTask> references, runs;
  std::vector<Task> reference_tasks, run_tasks;
  std::set<std::size_t> fresh_references;  // scenes whose reference is computed now
  for (std::size_t s = 0; s < study_.scenes.size(); ++s) {
    const Scene& scene = study_.scenes[s];
    const int vertices = scene.rows * scene.cols;
    bool all_resumed = true;
    for (std::size_t i = 0; i < runs_.size(); ++i) all_resumed = all_resumed && rows_.resumed(slot(s, i));
    if (!all_resumed && !fs::exists(reference_file(scene))) {
      const double cost =
          scene.frames * frame_cost(reference_method(), 0, is_converged_run({reference_method(), 0}), vertices);
      references.push_back({0, cost, "reference " + resolution_text(scene) + "/" + motion_text(scene)});
      reference_tasks.push_back({s, -1});
      fresh_references.insert(s);
    }
    for (int i = 0; i < static_cast<int>(runs_.size()); ++i) {
      const RunSpec& run = runs_[i];
      if (rows_.resumed(slot(s, i))) continue;
      if (is_reference_run(run) && fresh_references.count(s) && !study_.warm_start && study_.reference == "newton")
        continue;
      const double cost = scene.frames * frame_cost(run.method, run.budget, is_converged_run(run), vertices);
      runs.push_back({1, cost, run_label(run, scene)});
      run_tasks.push_back({s, i});
    }
  }
  tasks_ = reference_tasks;
  tasks_.insert(tasks_.end(), run_tasks.begin(), run_tasks.end());
  references.insert(references.end(), runs.begin(), runs.end());
  return references;
}

NewtonParams CompareSweep::reference_params() const {
  NewtonParams params;
  params.escape_saddles = study_.reference == "newton-min";
  return params;
}

std::string CompareSweep::reference_file(const Scene& scene) const {
  return newton_reference_path(study_.out, resolution_text(scene) + "_" + motion_text(scene), scene,
                               NewtonOptimizer(reference_params()).settings());
}

std::string CompareSweep::run_label(const RunSpec& run, const Scene& scene) const {
  return run.method + (run.budget ? " N=" + std::to_string(run.budget) : "") + " " + resolution_text(scene) + "/" +
         motion_text(scene);
}

StepCallback CompareSweep::progress(SweepTaskRun<CompareTaskResult>& task, const std::string& label) const {
  const double cost = runner_->tasks()[task.task()].cost;
  return [&task, label, cost](int done, int total, const StepRecord& s) {
    char status[160];
    std::snprintf(status, sizeof status, "%s: %.1f ms/step, strain %.0f%%", label.c_str(), s.wall_ms,
                  100 * s.max_strain);
    task.progress(cost * done / std::max(total, 1), status);
  };
}

RunResult CompareSweep::new_result(std::size_t s, const RunSpec& run) const {
  RunResult r;
  r.spec = run;
  r.resolution = resolution_text(study_.scenes[s]);
  r.motion = motion_text(study_.scenes[s]);
  r.frames_requested = study_.scenes[s].frames;
  return r;
}

OptimizerChoice CompareSweep::choice_of(const RunSpec& run) const {
  OptimizerChoice choice = study_.settings;
  choice.name = run.method;
  choice.iterations = run.budget;
  return choice;
}

void CompareSweep::run(std::size_t task, SweepTaskRun<CompareTaskResult>& run) {
  if (tasks_[task].run < 0)
    run_reference(task, run);
  else
    run_method(task, run);
}

// A scene's Newton reference, written to the output directory for every rank; the converged
// Newton run's row where the plan has one, measured on the reference rollout itself.
void CompareSweep::run_reference(std::size_t task, SweepTaskRun<CompareTaskResult>& run) {
  const std::size_t s = tasks_[task].scene;
  const Scene& scene = study_.scenes[s];
  NewtonOptimizer newton(reference_params());
  RolloutOptions options;
  options.solve = NewtonOptimizer::reference_solve_options();
  ResolvedScene resolved = resolve(scene);
  const TimedRollout reference = timed_rollout(resolved, newton, options, progress(run, runner_->tasks()[task].label));
  write_rollout_file(reference_file(scene), reference.rollout, scene, newton.settings());
  if (reference.rollout.diverged)
    SweepRunner::print_line("warning: the Newton reference of %s/%s %s\n", resolution_text(scene).c_str(),
                            motion_text(scene).c_str(), reference.rollout.divergence.c_str());
  // A ruler that did not reach its tolerance on some step is no ruler there: said, not hidden in the means.
  const int steps = static_cast<int>(reference.rollout.steps.size());
  const int unconverged = steps - reference.rollout.converged_steps();
  const std::string unconverged_text =
      unconverged > 0 ? std::to_string(unconverged) + " of " + std::to_string(steps) + " steps not converged" : "";
  if (unconverged > 0)
    SweepRunner::print_line("warning: the Newton reference of %s/%s: %s\n", resolution_text(scene).c_str(),
                            motion_text(scene).c_str(), unconverged_text.c_str());
  const auto converged = std::find_if(runs_.begin(), runs_.end(), is_reference_run);
  // The converged newton run is the reference rollout itself only where newton is the reference.
  const bool newton_row = study_.reference == "newton" && converged != runs_.end() &&
                          !rows_.resumed(slot(s, converged - runs_.begin())) && !study_.warm_start;
  const bool later = later_scenes_.count(s) > 0;
  CompareTaskResult result;
  if (newton_row || later) {
    context_ = make_compare_scene(study_, s, std::move(resolved), frames_of(reference.rollout));
    result.states = static_cast<int>(context_.bench->steps().size());
  }
  if (newton_row) {
    RunResult row = new_result(s, *converged);
    row.note = "the reference rollout itself";
    measure_run(study_, context_, choice_of(*converged), newton, reference, row);
    if (row.diverged) row.note += "; " + reference.rollout.divergence;
    if (unconverged > 0) row.note += "; " + unconverged_text;
    result.row = row;
  }
  if (later) {
    kept_.emplace(s, std::move(context_));
    context_ = CompareScene();
  }
  run.emit(result);
}

// One run on one scene; an optimizer that throws gives a row marked "error", not a stop.
void CompareSweep::run_method(std::size_t task, SweepTaskRun<CompareTaskResult>& run) {
  const std::size_t s = tasks_[task].scene;
  const RunSpec& spec = runs_[tasks_[task].run];
  RunResult r = new_result(s, spec);
  OptimizerChoice choice = choice_of(spec);
  if (method_traits(spec.method).learning_rate) {
    const LearningRate& lr = learning_rates_[{spec.method, spec.budget}];
    choice.learning_rate = r.lr = lr.value;
    r.lr_source = lr.source;
  }
  CompareScene& c = scene_context(s);
  try {
    const auto optimizer = choice.make();
    RolloutOptions options;
    options.solve = choice.solve_options();
    options.warm_start = study_.warm_start;
    const TimedRollout timed =
        timed_rollout(*c.resolved, *optimizer, options, progress(run, runner_->tasks()[task].label));
    measure_run(study_, c, choice, *optimizer, timed, r);
  } catch (const std::exception& e) {
    r.failed = true;
    r.note = std::string("failed: ") + e.what();
  }
  run.emit({static_cast<int>(c.bench->steps().size()), r});
}

CompareScene& CompareSweep::scene_context(std::size_t s) {
  if (context_.scene == s) return context_;
  if (const auto it = kept_.find(s); it != kept_.end()) {
    context_ = std::move(it->second);
    kept_.erase(it);
    return context_;
  }
  const Scene& scene = study_.scenes[s];
  const std::string cache = reference_file(scene);
  if (comm_.is_root())
    SweepRunner::print_line("reference %s/%s: cached %s\n", resolution_text(scene).c_str(), motion_text(scene).c_str(),
                            cache.c_str());
  context_ = make_compare_scene(study_, s, resolve(scene), read_trajectory_frames(cache));
  return context_;
}

// Rank 0 records a task's result: its scene's reference states, and its row, after which the
// outputs are rewritten and the run's line printed.
void CompareSweep::record(std::size_t task, const CompareTaskResult& result) {
  if (result.states > 0) reference_states_.insert(result.states);
  if (!result.row) return;
  const Task& t = tasks_[task];
  const int run =
      t.run >= 0 ? t.run : static_cast<int>(std::find_if(runs_.begin(), runs_.end(), is_reference_run) - runs_.begin());
  rows_.finish(slot(t.scene, run), *result.row);
  const std::vector<RunResult> results = all_results();
  write_table(results);
  write_outputs(results, "in progress, " + std::to_string(results.size() - unplanned_.size()) + " of " +
                             std::to_string(runs_.size() * study_.scenes.size()) + " runs done");
  const RunResult& r = *result.row;
  SweepRunner::print_line(
      "%-26s %8.2f ms/frame (cpu share %.2f)  e_CD %8.3f  e_3D %8.3f  step err %9.3g  strain %6.1f%%  %s\n",
      run_label(runs_[run], study_.scenes[t.scene]).c_str(), r.ms, r.cpu_share, 1e3 * r.e_cd, 1e2 * r.e_3d, r.step_mean,
      100 * r.strain, r.failed ? r.note.c_str() : (r.diverged ? "DIVERGED" : "ok"));
}

// "<states>\n<the encoded row, or nothing>"
std::string CompareSweep::encode(const CompareTaskResult& result) const {
  return std::to_string(result.states) + "\n" + (result.row ? encode_run_result(*result.row) : std::string());
}

CompareTaskResult CompareSweep::decode(const std::string& text) const {
  const std::size_t end = text.find('\n');
  CompareTaskResult result;
  parse_int(std::string_view(text).substr(0, end), result.states);
  // The row is the rest of the text (a note may hold line breaks).
  if (end + 1 < text.size()) result.row = decode_run_result(text.substr(end + 1));
  return result;
}

}  // namespace fnopt
