// compare's outputs on rank 0 (CompareSweep, studies/compare/compare_sweep.hpp): compare.csv, compare.svg
// and report.md, rewritten after every run, and what the console shows.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/studies/compare/compare_rows.hpp>
#include <fnopt/studies/compare/compare_sweep.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace fs = std::filesystem;

// compare.csv's rows in the order of a one-process run (sweep_rows.hpp), the frontier marked.
std::vector<RunResult> CompareSweep::all_results() const {
  std::vector<RunResult> results = unplanned_;
  rows_.visit(
      [&](std::size_t slot, const auto& row) { results.push_back(run_result_of_row(runs_[slot % runs_.size()], row)); },
      [&](std::size_t, const RunResult& result) { results.push_back(result); });
  mark_frontier(results, study_.threads);
  return results;
}

CsvTable CompareSweep::write_table(const std::vector<RunResult>& results) const {
  CsvTable table(compare_columns());
  for (const RunResult& r : results) table.add_row(compare_csv_row(r, study_.threads));
  table.write(csv_path_);
  return table;
}

CompareReport CompareSweep::make_report() const {
  const std::vector<std::string>& methods = study_.methods;
  CompareReport report;
  report.directory = study_.out;
  report.command_line = study_.command_line;
  report.scene_text = to_scene_text(study_.scenes.front());
  report.resolutions = resolutions_;
  report.motions = motions_;
  report.methods = methods;
  report.threads = study_.threads;
  report.preset = study_.preset;
  report.error_levels = study_.error_levels;
  report.superres =
      study_.preset == "superres" ||
      (std::any_of(methods.begin(), methods.end(), [](const std::string& m) { return method_traits(m).learned; }) &&
       std::any_of(methods.begin(), methods.end(), is_interpolated_method));
  return report;
}

// compare.svg and report.md (and superres.svg).
void CompareSweep::write_outputs(const std::vector<RunResult>& results, const std::string& status) const {
  const Scene& base = study_.scenes.front();
  // Frames and reference states as the rows have them, which a --resume may mix.
  std::set<int> frames;
  for (const RunResult& r : results) frames.insert(r.frames_requested);
  if (frames.empty()) frames.insert(base.frames);
  std::vector<std::string> frame_texts, state_texts;
  for (int f : frames) frame_texts.push_back(std::to_string(f));
  for (std::size_t n : reference_states_) state_texts.push_back(std::to_string(n));
  std::vector<std::string> notes = {
      joined(frame_texts, " or ") + " frames" + (frames.size() > 1 ? " (see each row)" : "") +
          " at dt = " + dt_text(base.dt) +
          " s; N = iterations per time step; errors vs the converged " +
          (study_.reference == "newton-min" ? std::string("newton-min (Newton that ends at minima) rollout")
                                            : std::string("Newton rollout")) +
          " (residual acceleration <= " +
          NewtonOptimizer::reference_stop_text() + "); " + "per-step error on " +
          (state_texts.empty() ? std::to_string(study_.step_samples) : joined(state_texts, " or ")) +
          " reference states; e_CD with " + std::to_string(study_.chamfer.samples) + " points per mesh",
      "motions: " + joined(motions_)};
  if (!lr_notes_.empty()) notes.push_back("learning rates (swept on the first scene): " + joined(lr_notes_));
  write_svg(svg_path_, make_compare_plot(results, study_.methods, resolutions_, motions_, study_.threads, notes));
  CompareReport report = report_;
  report.notes = notes;
  report.status = status;
  write_compare_report(report, results);
}

void CompareSweep::print_banner() const {
  const std::size_t scenes = study_.scenes.size();
  const int threads = study_.threads;
  std::fprintf(stderr,
               "fnopt compare: %zu scene%s (res %s; motions %s), %zu runs each, %d frames, %d thread%s (fixed for "
               "every timing)%s, output %s\n",
               scenes, scenes == 1 ? "" : "s", study_.resolutions_text.c_str(), joined(motions_).c_str(), runs_.size(),
               study_.scenes.front().frames, threads, threads == 1 ? "" : "s",
               comm_.size() > 1 ? (", " + std::to_string(comm_.size()) + " processes").c_str() : "",
               study_.out.c_str());
  if (resumed_.size() > 0)
    std::fprintf(stderr, "resuming: %zu finished runs in %s\n", resumed_.size(), csv_path_.c_str());
}

void CompareSweep::print_summary(const std::vector<RunResult>& results, const CsvTable& table) const {
  const int threads = study_.threads;
  std::printf("%s", table.text().c_str());
  for (const std::string& res : resolutions_) {
    std::printf("fastest at %s (mean over the motions, runs that diverged nowhere):", resolution_title(res).c_str());
    for (const LevelWinner& w : fastest_within(results, res, study_.error_levels, threads))
      std::printf("  e_CD x10^3 <= %g: %s", 1e3 * w.level,
                  w.method.empty() ? "none"
                                   : (w.method + " N=" + std::to_string(w.budget) + " (" + CsvTable::number(w.ms, 3) +
                                      " ms/frame, " + CsvTable::number(1e3 * w.e_cd, 3) + ")")
                                         .c_str());
    std::printf("\n");
  }
  std::printf("wrote %s, %s and %s (%d thread%s)\n", csv_path_.c_str(), svg_path_.c_str(),
              (fs::path(study_.out) / "report.md").string().c_str(), threads, threads == 1 ? "" : "s");
}

}  // namespace fnopt
