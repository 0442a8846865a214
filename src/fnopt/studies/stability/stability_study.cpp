#include <fnopt/studies/stability/stability_study.hpp>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>

#include <fnopt/methods/registry.hpp>
#include <fnopt/studies/sweep/resumed_rows.hpp>
#include <fnopt/studies/stability/stability_report.hpp>
#include <fnopt/studies/sweep/sweep_rows.hpp>
#include <fnopt/studies/sweep/sweep_runner.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

// Relative cost of one frame (methods/registry.hpp), for the schedule and the ETA only.
double frame_cost(const StabilityMethod& m, const Scene& scene) {
  return fnopt::frame_cost(m.method, m.solve.max_iterations, m.reference && m.solve.to_tolerance(),
                           scene.rows * scene.cols);
}

void print_row(const StabilityRow& r) {
  SweepRunner::print_line(
      "%-22s %-9s %-20s %-8s %4d/%-4d strain %7.1f%%  growth %7.3g  e3D %7.3g  %8.2f ms/frame%s%s\n",
      r.case_name.c_str(), r.method.c_str(), budget_text(r.solve).c_str(), to_string(r.outcome), r.frames_done,
      r.frames_requested, 100 * r.max_strain, r.energy_growth, 100 * r.e3d, r.ms_per_frame,
      r.reason.empty() ? "" : "  ", r.reason.c_str());
}

std::string started_now() {
  char text[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M", std::localtime(&now));
  return text;
}

// One row of one method on one case, as measured and as its CSV cells: rows from other ranks
// arrive as the cells.
struct FinishedRow {
  std::size_t method = 0;  // into StabilityStudy::methods
  StabilityRow row;
  std::vector<std::string> cells;
};

// The study as a sweep (studies/sweep/sweep_runner.hpp): one task per case not resumed whole, its
// Newton reference and every row measured against it (the reference lives in memory, so a case
// stays on one rank).
class StabilitySweep final : public SweepWork<FinishedRow> {
 public:
  StabilitySweep(const StabilityStudy& study, const Communicator& comm);
  void run_study();

  void run(std::size_t task, SweepTaskRun<FinishedRow>& run) override;
  void record(std::size_t task, const FinishedRow& row) override;
  void finished(std::size_t task) override;
  std::string encode(const FinishedRow& row) const override;
  FinishedRow decode(const std::string& text) const override;

 private:
  std::size_t slot(std::size_t k, std::size_t j) const { return k * study_.methods.size() + j; }
  std::vector<SweepTask> plan(double& resumed_cost);
  void print_banner() const;
  StabilityRun run_with_progress(const Scene& scene, const StabilityMethod& m, const std::string& label,
                                 SweepTaskRun<FinishedRow>& run, double& cost_done) const;
  void assemble();

  const StabilityStudy& study_;
  const Communicator& comm_;
  StabilityMethod reference_;  // the reference of every case: Newton at the suite's settings
  OptimizerFactory factory_;
  StabilityReportFiles files_;
  std::string csv_;
  ResumedRows resumed_;  // --resume: the earlier stability.csv's rows
  SweepRows<FinishedRow> rows_;
  std::vector<std::size_t> cases_;  // of the tasks
  // Rank 0: stability.csv as one process writes it, and the measured rows of this plan.
  CsvTable table_;
  std::vector<StabilityRow> measured_;
};

StabilitySweep::StabilitySweep(const StabilityStudy& study, const Communicator& comm)
    : study_(study),
      comm_(comm),
      files_{(fs::path(study.out) / "stability.svg").string(), (fs::path(study.out) / "report.md").string(),
             started_now()},
      csv_((fs::path(study.out) / "stability.csv").string()),
      resumed_(csv_, stability_columns(), {"case", "method", "N"}, study.resume, "stability"),
      rows_(resumed_),
      table_(stability_columns()) {
  OptimizerChoice reference;
  reference.name = reference_method();
  reference_ = {reference.name, reference.solve_options(), true};
  for (const auto& m : study.methods)
    if (m.reference) reference_ = m;
  factory_ = [&study](const std::string& method) {
    OptimizerChoice choice;
    choice.name = method;
    choice.model = study.model;
    return choice.make();
  };
  for (const StabilityCase& c : study.cases)
    for (const StabilityMethod& m : study.methods) rows_.plan({c.name, m.method, budget_text(m.solve)});
}

void StabilitySweep::run_study() {
  double resumed_cost = 0.0;
  std::vector<SweepTask> tasks = plan(resumed_cost);
  SweepRunner runner("stability", std::move(tasks), comm_, resumed_cost);
  if (comm_.is_root()) print_banner();
  runner.run_phase(0, *this);
  if (!comm_.is_root()) return;
  assemble();
  runner.finish();
  table_.write(csv_);
  write_stability_report(study_, files_, measured_, table_, true);
  std::printf("%s", stability_console_table(measured_).c_str());
  std::printf("\nwhat fails where:\n");
  for (const auto& line : stability_summary(measured_, study_.method_names)) std::printf("- %s\n", line.c_str());
  std::printf("wrote %s, %s and %s (%d thread%s)\n", csv_.c_str(), files_.svg.c_str(), files_.report.c_str(),
              study_.threads, study_.threads == 1 ? "" : "s");
}

// A case's task costs its rows not resumed, and its reference where no row is the reference.
std::vector<SweepTask> StabilitySweep::plan(double& resumed_cost) {
  const auto& methods = study_.methods;
  const bool reference_listed =
      std::any_of(methods.begin(), methods.end(), [](const StabilityMethod& m) { return m.reference; });
  std::vector<SweepTask> tasks;
  for (std::size_t k = 0; k < study_.cases.size(); ++k) {
    const Scene s = study_.cases[k].apply(study_.base);
    double cost = 0.0;
    bool all_resumed = true;
    for (std::size_t j = 0; j < methods.size(); ++j) {
      if (rows_.resumed(slot(k, j)))
        resumed_cost += s.frames * frame_cost(methods[j], s);
      else
        cost += s.frames * frame_cost(methods[j], s), all_resumed = false;
    }
    if (all_resumed) continue;
    tasks.push_back({0, cost + (reference_listed ? 0.0 : s.frames * frame_cost(reference_, s)), study_.cases[k].name});
    cases_.push_back(k);
  }
  return tasks;
}

void StabilitySweep::print_banner() const {
  const Scene& base = study_.base;
  const int threads = study_.threads;
  if (resumed_.size() > 0) std::fprintf(stderr, "resuming: %zu finished rows in %s\n", resumed_.size(), csv_.c_str());
  std::string method_text;
  for (const auto& m : study_.methods)
    method_text += (method_text.empty() ? "" : ", ") + m.method + " " + budget_text(m.solve);
  std::fprintf(stderr,
               "fnopt stability: %zu case%s x %zu optimizers (%s), base %dx%d, %d frames at dt %s, %d thread%s%s, "
               "output %s\n",
               study_.cases.size(), study_.cases.size() == 1 ? "" : "s", study_.methods.size(), method_text.c_str(),
               base.rows, base.cols, base.frames, dt_text(base.dt).c_str(), threads, threads == 1 ? "" : "s",
               comm_.size() > 1 ? (", " + std::to_string(comm_.size()) + " processes").c_str() : "",
               study_.out.c_str());
}

StabilityRun StabilitySweep::run_with_progress(const Scene& scene, const StabilityMethod& m, const std::string& label,
                                               SweepTaskRun<FinishedRow>& run, double& cost_done) const {
  const double weight = frame_cost(m, scene), start = cost_done;
  StabilityRun result = run_stability_rollout(scene, m, factory_, {}, [&](int done, int, const StepRecord& s) {
    char status[160];
    std::snprintf(status, sizeof status, "%s: %.1f ms/step, strain %.0f%%", label.c_str(), s.wall_ms,
                  100 * s.max_strain);
    run.progress(start + done * weight, status);
  });
  cost_done += scene.frames * weight;
  return result;
}

void StabilitySweep::run(std::size_t task, SweepTaskRun<FinishedRow>& run) {
  const StabilityCase& c = study_.cases[cases_[task]];
  const Scene scene = c.apply(study_.base);
  double cost_done = 0.0;
  const StabilityRun reference = run_with_progress(scene, reference_, "newton reference " + c.name, run, cost_done);
  if (reference.failed || reference.rollout.diverged)
    SweepRunner::print_line("warning: the Newton reference of %s %s%s\n", c.name.c_str(),
                            reference.failed ? "failed: " : "",
                            reference.failed ? reference.error.c_str() : reference.rollout.divergence.c_str());
  for (std::size_t j = 0; j < study_.methods.size(); ++j) {
    const StabilityMethod& m = study_.methods[j];
    if (rows_.resumed(slot(cases_[task], j))) continue;
    const StabilityRun own =
        m.reference ? StabilityRun{} : run_with_progress(scene, m, m.method + " " + c.name, run, cost_done);
    const StabilityRun& ran = m.reference ? reference : own;  // the reference is counted above
    StabilityRow row = stability_row(c.name, m, ran, &reference);
    count_intersections(scene, ran, row);
    run.emit({j, row, stability_csv_row(row)});
  }
}

// Rank 0 records a finished row, rewrites the CSV and prints it.
void StabilitySweep::record(std::size_t task, const FinishedRow& finished) {
  const std::size_t k = cases_[task];
  rows_.finish(slot(k, finished.method), finished);
  assemble();
  table_.write(csv_);
  const StabilityRow& row = finished.row;
  print_row(row);
  if (study_.methods[finished.method].reference && row.unconverged_steps > 0)
    SweepRunner::print_line("warning: newton on %s: %d step%s did not converge (%s)\n", study_.cases[k].name.c_str(),
                            row.unconverged_steps, row.unconverged_steps == 1 ? "" : "s",
                            row.unconverged_statuses.c_str());
}

void StabilitySweep::finished(std::size_t) { write_stability_report(study_, files_, measured_, table_, false); }

// "<method index>" and the row's cells, separated by the ASCII unit separator.
std::string StabilitySweep::encode(const FinishedRow& row) const {
  std::string text = std::to_string(row.method);
  for (const std::string& cell : row.cells) text += '\x1f' + cell;
  return text;
}

FinishedRow StabilitySweep::decode(const std::string& text) const {
  FinishedRow finished;
  for (std::string_view cell : split(text, '\x1f')) finished.cells.emplace_back(cell);
  int method = 0;
  parse_int(finished.cells.front(), method);
  finished.cells.erase(finished.cells.begin());
  finished.method = static_cast<std::size_t>(method);
  finished.row = stability_row_from_csv(finished.cells);
  finished.row.reference = study_.methods[finished.method].reference;
  return finished;
}

// stability.csv in the order of a one-process run (sweep_rows.hpp), and the measured rows.
void StabilitySweep::assemble() {
  measured_.clear();
  table_ = CsvTable(stability_columns());
  for (const auto& cells : rows_.unplanned()) table_.add_row(cells);
  rows_.visit(
      [&](std::size_t slot, const ResumedRows::Row& earlier) {
        measured_.push_back(stability_row_from_csv(earlier));
        measured_.back().reference = study_.methods[slot % study_.methods.size()].reference;
        table_.add_row(earlier);
      },
      [&](std::size_t, const FinishedRow& finished) {
        measured_.push_back(finished.row);
        table_.add_row(finished.cells);
      });
}

}  // namespace

void run_stability_study(const StabilityStudy& study, const Communicator& comm) {
  StabilitySweep(study, comm).run_study();
}

}  // namespace fnopt
