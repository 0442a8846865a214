#include <fnopt/studies/repulsion/repulsion_study.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/metrics/self_contact.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/studies/repulsion/repulsion_report.hpp>
#include <fnopt/studies/sweep/resumed_rows.hpp>
#include <fnopt/studies/sweep/sweep_rows.hpp>
#include <fnopt/studies/sweep/sweep_runner.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

using Rows = std::vector<std::vector<std::string>>;

// One finished run: its row of repulsion.csv and its rows of repulsion_energy.csv.
struct RunRows {
  std::vector<std::string> row;
  Rows energy;
};

RunRows run_one(const Scene& base, const std::string& preset, bool repulsion, const OptimizerChoice& choice,
                const StepCallback& on_step) {
  Scene scene = base;
  apply_scene_setting(scene, "handles", preset);
  apply_scene_setting(scene, "repulsion", repulsion ? "true" : "false");
  // The study measures self-repulsion alone: self-contact, which takes its place on these presets
  // by default, stays off.
  apply_scene_setting(scene, "self-contact", "false");
  const auto optimizer = choice.make();
  RolloutOptions options;
  options.solve = choice.solve_options();
  const bool tolerance = options.solve.to_tolerance();
  const RolloutResult rollout = run_rollout(resolve(scene), *optimizer, options, on_step);

  RunRows result;
  const std::string on_off = repulsion ? "on" : "off";
  std::vector<SelfContactFrame> frames;
  SpatialHash hash;
  VecX x;
  for (std::size_t t = 0; t < rollout.positions.size(); ++t) {
    x = rollout.positions[t].cast<double>();
    frames.push_back(measure_self_contact(rollout.grid, x, hash));
    result.energy.push_back({preset, on_off, choice.name, CsvTable::number(rollout.times[t], 8),
                             CsvTable::number(frames.back().energy, 6)});
  }
  const SelfContactSummary s = summarize_self_contact(frames);
  const int steps = static_cast<int>(rollout.steps.size());
  result.row = {preset,
                on_off,
                choice.name,
                std::to_string(base.rows),
                std::to_string(base.frames),
                std::to_string(static_cast<int>(rollout.positions.size()) - 1),
                CsvTable::number(rollout.mean_step_ms(), 4),
                CsvTable::number(steps ? static_cast<double>(rollout.total_iterations()) / steps : 0.0, 4),
                tolerance ? std::to_string(rollout.converged_steps()) + "/" + std::to_string(steps) : "budget",
                CsvTable::number(s.mean_energy, 4),
                CsvTable::number(s.max_energy, 4),
                CsvTable::number(s.share_above[0], 4),
                CsvTable::number(s.share_above[1], 4),
                CsvTable::number(s.share_above[2], 4),
                std::to_string(s.max_pairs_half),
                std::to_string(s.max_pairs_quarter),
                CsvTable::number(s.frames_with_quarter, 4),
                CsvTable::number(s.min_distance, 4),
                CsvTable::number(100.0 * rollout.max_strain(), 4),
                rollout.diverged ? "yes" : "no"};
  return result;
}

// The study as a sweep (studies/sweep/sweep_runner.hpp): one task per preset, repulsion off or on, and
// optimizer, in that order.
class RepulsionSweep final : public SweepWork<RunRows> {
 public:
  RepulsionSweep(const RepulsionStudy& study, const Communicator& comm);
  void run_study();

  void run(std::size_t task, SweepTaskRun<RunRows>& run) override;
  void record(std::size_t task, const RunRows& rows) override;
  std::string encode(const RunRows& rows) const override;
  RunRows decode(const std::string& text) const override;

 private:
  struct Run {
    std::string preset;
    bool repulsion = false;
    std::size_t optimizer = 0;  // into RepulsionStudy::optimizers
  };
  double cost(const OptimizerChoice& choice) const;
  void print_banner() const;
  // Both files as one process writes them (sweep_rows.hpp): runs and energy rows.
  std::pair<Rows, Rows> assemble(bool with_unplanned) const;

  const RepulsionStudy& study_;
  const Communicator& comm_;
  std::string csv_path_, energy_path_;
  ResumedRows resumed_;                      // --resume: the earlier repulsion.csv's rows
  std::map<std::string, Rows> kept_energy_;  // the energy rows of the earlier runs, by run key
  std::vector<Run> runs_;                    // in plan order, one slot each
  SweepRows<RunRows> rows_;
  std::vector<std::size_t> slots_;  // of the tasks
};

RepulsionSweep::RepulsionSweep(const RepulsionStudy& study, const Communicator& comm)
    : study_(study),
      comm_(comm),
      csv_path_((fs::path(study.out) / "repulsion.csv").string()),
      energy_path_((fs::path(study.out) / "repulsion_energy.csv").string()),
      resumed_(csv_path_, repulsion_run_columns(), {"preset", "repulsion", "optimizer"}, study.resume,
               "repulsion-study"),
      rows_(resumed_) {
  // The energy rows of the runs kept, by run key (several rows per run: ResumedRows keeps one).
  if (resumed_.size() > 0) {
    require(fs::exists(energy_path_), "resume", energy_path_ + " is missing: cannot redraw the finished runs");
    const CsvTable earlier = CsvTable::read(energy_path_);
    require(earlier.columns() == repulsion_energy_columns(), "resume",
            energy_path_ + ": written by another version of repulsion-study: cannot resume");
    for (const auto& row : earlier.rows()) kept_energy_[ResumedRows::key({row[0], row[1], row[2]})].push_back(row);
  }
  for (const std::string& preset : repulsion_presets())
    for (bool repulsion : {false, true})
      for (std::size_t i = 0; i < study.optimizers.size(); ++i) {
        runs_.push_back({preset, repulsion, i});
        rows_.plan({preset, repulsion ? "on" : "off", study.optimizers[i].name});
      }
}

// Frame-cost units (methods/registry.hpp), as compare and stability count them.
double RepulsionSweep::cost(const OptimizerChoice& choice) const {
  const InnerSolveOptions solve = choice.solve_options();
  const Scene& base = study_.base;
  return base.frames * frame_cost(choice.name, solve.max_iterations, solve.to_tolerance(), base.rows * base.cols);
}

void RepulsionSweep::run_study() {
  std::vector<SweepTask> tasks;
  double resumed_cost = 0.0;
  for (std::size_t slot = 0; slot < runs_.size(); ++slot) {
    const Run& run = runs_[slot];
    const OptimizerChoice& choice = study_.optimizers[run.optimizer];
    if (rows_.resumed(slot)) {
      resumed_cost += cost(choice);
      continue;
    }
    tasks.push_back({0, cost(choice), run.preset + " " + (run.repulsion ? "on" : "off") + " " + choice.name});
    slots_.push_back(slot);
  }
  SweepRunner runner("repulsion-study", std::move(tasks), comm_, resumed_cost);
  if (comm_.is_root()) print_banner();
  runner.run_phase(0, *this);
  if (!comm_.is_root()) return;
  runner.finish();
  write_repulsion_report(study_, assemble(false).first, assemble(true).second);
}

void RepulsionSweep::print_banner() const {
  const Scene& base = study_.base;
  if (resumed_.size() > 0)
    std::fprintf(stderr, "resuming: %zu finished runs in %s\n", resumed_.size(), csv_path_.c_str());
  std::fprintf(stderr,
               "fnopt repulsion-study: %dx%d grid, motion %s, %d frames, presets corner-center, single-mid-edge, "
               "corner; repulsion off/on (lambda %.4g N/m, delta = h); %zu optimizer%s; %d thread%s\n",
               base.rows, base.cols, base.motion.c_str(), base.frames, base.material.repulsion_stiffness,
               study_.optimizers.size(), study_.optimizers.size() == 1 ? "" : "s", study_.threads,
               study_.threads == 1 ? "" : "s");
}

void RepulsionSweep::run(std::size_t task, SweepTaskRun<RunRows>& run) {
  const Run& r = runs_[slots_[task]];
  const OptimizerChoice& choice = study_.optimizers[r.optimizer];
  const std::string label = r.preset + " " + (r.repulsion ? "on" : "off") + " " + choice.name;
  const double weight = cost(choice) / study_.base.frames;
  run.emit(run_one(study_.base, r.preset, r.repulsion, choice, [&](int done, int, const StepRecord& s) {
    char status[128];
    std::snprintf(status, sizeof status, "%s: %.1f ms/step, %d it", label.c_str(), s.wall_ms, s.iterations);
    run.progress(done * weight, status);
  }));
}

// Rank 0: both files hold every finished run after each one, so that an interrupted study resumes.
void RepulsionSweep::record(std::size_t task, const RunRows& rows) {
  rows_.finish(slots_[task], rows);
  const auto [runs, energy] = assemble(true);
  CsvTable run_table(repulsion_run_columns()), energy_table(repulsion_energy_columns());
  for (const auto& row : runs) run_table.add_row(row);
  for (const auto& row : energy) energy_table.add_row(row);
  energy_table.write(energy_path_);
  run_table.write(csv_path_);
}

std::pair<Rows, Rows> RepulsionSweep::assemble(bool with_unplanned) const {
  Rows runs, energy;
  auto add = [&](const std::vector<std::string>& row, const Rows& energy_rows) {
    runs.push_back(row);
    energy.insert(energy.end(), energy_rows.begin(), energy_rows.end());
  };
  auto kept = [&](const std::vector<std::string>& row) {
    const auto it = kept_energy_.find(ResumedRows::key({row[0], row[1], row[2]}));
    return it == kept_energy_.end() ? Rows() : it->second;
  };
  if (with_unplanned)
    for (const auto& row : rows_.unplanned()) add(row, kept(row));
  rows_.visit([&](std::size_t, const std::vector<std::string>& row) { add(row, kept(row)); },
              [&](std::size_t, const RunRows& rows) { add(rows.row, rows.energy); });
  return {runs, energy};
}

// The run's row, then its energy rows: cells separated by the ASCII unit separator, rows by the
// record separator.
std::string RepulsionSweep::encode(const RunRows& rows) const {
  std::string text;
  auto add = [&](const std::vector<std::string>& row) {
    for (std::size_t c = 0; c < row.size(); ++c) text += (c ? "\x1f" : "") + row[c];
    text += '\x1e';
  };
  add(rows.row);
  for (const auto& row : rows.energy) add(row);
  return text;
}

RunRows RepulsionSweep::decode(const std::string& text) const {
  RunRows rows;
  for (std::string_view line : split(text, '\x1e')) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    for (std::string_view cell : split(line, '\x1f')) cells.emplace_back(cell);
    if (rows.row.empty())
      rows.row = std::move(cells);
    else
      rows.energy.push_back(std::move(cells));
  }
  return rows;
}

}  // namespace

const std::vector<std::string>& repulsion_presets() {
  static const std::vector<std::string> presets = {"corner-center", "single-mid-edge", "corner"};
  return presets;
}

void run_repulsion_study(const RepulsionStudy& study, const Communicator& comm) {
  RepulsionSweep(study, comm).run_study();
}

}  // namespace fnopt
