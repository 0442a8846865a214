#include <fnopt/studies/compare/compare_report.hpp>

#include <filesystem>

#include <fnopt/io/markdown_report.hpp>
#include <fnopt/studies/compare/compare_aggregate.hpp>
#include <fnopt/studies/compare/superres_report.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/version.hpp>

namespace fnopt {

namespace fs = std::filesystem;

void write_compare_report(const CompareReport& report, const std::vector<RunResult>& results) {
  MarkdownReport md("fnopt compare" + (report.preset.empty() ? "" : ": the " + report.preset + " study"));
  md.paragraph("Status: " + report.status + ". Written by `fnopt compare` (fnopt " + FNOPT_VERSION +
               "); the numbers are in compare.csv (one row per run).");
  md.heading("Command");
  md.code(report.command_line);
  md.heading("Scenes");
  std::vector<std::string> scene_items = {
      "resolutions: " + joined(report.resolutions) +
          " (N: N x N vertices; RxC: R rows x C columns; the cloth's "
          "longer edge has the scene's size, cells are square)",
      "optimizers: " + joined(report.methods),
      std::to_string(report.threads) + " thread" + (report.threads == 1 ? "" : "s") + " for every timing"};
  for (const auto& note : report.notes) scene_items.push_back(note);
  md.bullets(scene_items);
  md.paragraph("The resolved scene (of the first resolution; the others differ in `rows` and `cols` only):");
  md.code(report.scene_text);

  md.heading("Results per resolution");
  md.paragraph(std::string("Errors against the Newton reference rollout of the same scene (e_CD x 10^3: Chamfer; ") +
               "e_3D x 10^2: relative vertex error; per-step error: the median over the reference's states of "
               "(L(a_N) - L*)/(L(a_0) - L*), whose mean one state where Newton's step is poor can swamp). "
               "ms/frame: " +
               (report.threads == 1 ? "one thread, after warm-up, wall time x the CPU share the process got"
                                    : "after warm-up, wall time") +
               (report.motions.size() > 1 ? "; every number is the mean over the motions" : "") + ".");
  const std::vector<std::string> header = {"method",         "N",       "ms/frame", "e_CD x10^3", "e_3D x10^2",
                                           "per-step error (median)", "diverged"};
  for (const auto& res : report.resolutions) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& method : report.methods)
      for (int budget : budgets_of(results, method)) {
        const Aggregate a = aggregate(results, res, method, budget, report.threads);
        if (a.runs == 0) continue;
        rows.push_back({method, budget_text({method, budget}), report_number(a.ms), report_number(1e3 * a.e_cd),
                        report_number(1e2 * a.e_3d), report_number(a.step), diverged_text(a)});
      }
    if (rows.empty()) continue;
    md.heading(resolution_title(res) + " (" + std::to_string(vertex_count_of(res)) + " vertices)", 3);
    md.table(header, rows);
  }
  md.heading("The error-time frontier");
  md.paragraph(
      "A run is on the frontier of its scene when no other run of the scene is as fast and as close to "
      "Newton, and better in one (compare.csv, column frontier). Per resolution, over the means across "
      "motions of the runs that diverged nowhere: the fastest method within each e_CD level.");
  for (const auto& res : report.resolutions) {
    std::vector<std::vector<std::string>> rows;
    for (const LevelWinner& w : fastest_within(results, res, report.error_levels, report.threads))
      rows.push_back({report_number(1e3 * w.level),
                      w.method.empty() ? "none reaches it" : method_label(w.method, w.budget), report_number(w.ms),
                      report_number(1e3 * w.e_cd)});
    std::vector<std::string> on_frontier;
    for (const auto& r : results)
      if (r.resolution == res && r.frontier)
        on_frontier.push_back(r.motion + ": " + method_label(r.spec.method, r.spec.budget));
    md.heading(resolution_title(res), 3);
    md.table({"e_CD x10^3 at most", "fastest", "ms/frame", "e_CD x10^3"}, rows);
    md.paragraph("On the frontier, per motion: " + joined(on_frontier, "; ") + ".");
  }

  md.heading("Error against run time");
  md.image("compare.svg", "error against ms/frame, one line per method through its budgets");

  if (report.superres) write_superres_section(md, report, results);
  md.write((fs::path(report.directory) / "report.md").string());
}

}  // namespace fnopt
