#include <fnopt/studies/stability/stability_summary.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/stability/stability_table.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// "self / mesh" intersection counts, "self" without a mesh, "" where not measured.
std::string crossings_text(const StabilityRow& r) {
  if (r.self_intersections < 0) return "";
  return std::to_string(r.self_intersections) +
         (r.mesh_intersections >= 0 ? " / " + std::to_string(r.mesh_intersections) : "");
}

}  // namespace

std::string stability_console_table(const std::vector<StabilityRow>& rows) {
  const std::vector<std::string> header = {"case",     "method",   "N",      "outcome",  "frames",
                                           "strain %", "E growth", "e3D e2", "ms/frame", "crossings", "unconverged"};
  std::vector<std::vector<std::string>> cells;
  for (const StabilityRow& r : rows) {
    std::string outcome = to_string(r.outcome);
    if (r.diverged_step > 0) outcome += " @" + std::to_string(r.diverged_step);
    std::string unconverged;
    if (r.outcome != StabilityOutcome::Error)
      unconverged = std::to_string(r.unconverged_steps) +
                    (r.unconverged_statuses.empty() ? "" : " (" + r.unconverged_statuses + ")");
    cells.push_back({r.case_name, r.method, budget_text(r.solve), outcome,
                     std::to_string(r.frames_done) + "/" + std::to_string(r.frames_requested),
                     stability_cell(1e2 * r.max_strain, 3), stability_cell(r.energy_growth, 3),
                     stability_cell(1e2 * r.e3d, 3), stability_cell(r.ms_per_frame, 3), crossings_text(r),
                     unconverged});
  }
  std::vector<std::size_t> width(header.size());
  for (std::size_t k = 0; k < header.size(); ++k) width[k] = header[k].size();
  for (const auto& row : cells)
    for (std::size_t k = 0; k < row.size(); ++k) width[k] = std::max(width[k], row[k].size());
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& row) {
    std::string text;
    for (std::size_t k = 0; k < row.size(); ++k) {
      const bool left = k <= 3 || k + 1 == row.size();
      const std::string pad(width[k] - row[k].size(), ' ');
      text += (k ? "  " : "") + (left ? row[k] + (k + 1 == row.size() ? "" : pad) : pad + row[k]);
    }
    out << text << "\n";
  };
  line(header);
  for (const auto& row : cells) line(row);
  for (const StabilityRow& r : rows)
    if (r.outcome != StabilityOutcome::Finished && !r.reason.empty())
      out << r.case_name << " / " << r.method << ": " << r.reason << "\n";
  return out.str();
}

std::vector<std::string> stability_summary(const std::vector<StabilityRow>& rows,
                                           const std::vector<std::string>& methods) {
  std::vector<std::string> lines;
  for (const std::string& method : methods) {
    int finished = 0, total = 0;
    std::vector<std::string> diverged, failed;
    for (const StabilityRow& r : rows) {
      if (r.method != method) continue;
      ++total;
      if (r.outcome == StabilityOutcome::Finished) ++finished;
      if (r.outcome == StabilityOutcome::Diverged)
        diverged.push_back(r.case_name + " (step " + std::to_string(r.diverged_step) + ")");
      if (r.outcome == StabilityOutcome::Error) failed.push_back(r.case_name);
    }
    if (total == 0) continue;
    std::string line = method + ": finished " + std::to_string(finished) + " of " + std::to_string(total) + " cases";
    if (!diverged.empty()) line += "; diverged on " + joined(diverged);
    if (!failed.empty()) line += "; error on " + joined(failed);
    lines.push_back(line);
  }
  // Steps short of convergence: Newton (the reference) first, it must never fail silently.
  std::vector<std::string> unconverged;
  for (const StabilityRow& r : rows)
    if (r.unconverged_steps > 0)
      unconverged.push_back(r.method + " on " + r.case_name + ": " + std::to_string(r.unconverged_steps) + " step" +
                            (r.unconverged_steps == 1 ? "" : "s") + " (" + r.unconverged_statuses + ")");
  const bool has_newton = std::any_of(rows.begin(), rows.end(), [](const StabilityRow& r) {
    return r.reference && r.outcome != StabilityOutcome::Error;
  });
  const bool newton_clean = std::none_of(rows.begin(), rows.end(), [](const StabilityRow& r) {
    return r.reference && (r.unconverged_steps > 0 || r.outcome != StabilityOutcome::Finished);
  });
  if (has_newton && newton_clean) lines.push_back("newton converged every step of every case it ran");
  if (!unconverged.empty())
    lines.push_back("steps that stopped short of convergence (or on a failure): " + joined(unconverged));
  // Crossings, counted on every run of a contact case: the guarantee is none (docs/design.md §14).
  std::vector<std::string> crossed;
  int counted = 0;
  for (const StabilityRow& r : rows) {
    if (r.self_intersections < 0) continue;
    ++counted;
    if (r.self_intersections > 0 || r.mesh_intersections > 0)
      crossed.push_back(r.method + " on " + r.case_name + " (" + crossings_text(r) + ")");
  }
  if (counted > 0)
    lines.push_back(crossed.empty() ? "no self- or mesh intersection in any of the " + std::to_string(counted) +
                                          " runs of the contact cases"
                                    : "runs whose frames cross (self / mesh intersections): " + joined(crossed));
  std::vector<std::string> blowups;
  for (const StabilityRow& r : rows)
    if (r.outcome == StabilityOutcome::Finished && std::isfinite(r.energy_growth) && r.energy_growth > 2.0)
      blowups.push_back(r.method + " on " + r.case_name + " (x" + CsvTable::number(r.energy_growth, 3) + ")");
  if (!blowups.empty()) lines.push_back("finished but gained energy (growth > 2): " + joined(blowups));
  const StabilityRow* worst = nullptr;
  for (const StabilityRow& r : rows)
    if (!r.reference && r.outcome == StabilityOutcome::Finished && std::isfinite(r.e3d) &&
        (!worst || r.e3d > worst->e3d))
      worst = &r;
  if (worst)
    lines.push_back("largest e_3D x 10^2 among finished runs: " + CsvTable::number(1e2 * worst->e3d, 3) + " (" +
                    worst->method + " on " + worst->case_name + ")");
  return lines;
}

PlotFigure stability_plot(const std::vector<StabilityRow>& rows, const std::vector<StabilityCase>& cases,
                          const std::vector<std::string>& methods, const std::vector<std::string>& notes) {
  PlotFigure figure;
  figure.title = "fnopt stability: max strain and energy growth per case";
  figure.notes = notes;
  std::string legend;
  for (std::size_t k = 0; k < cases.size(); ++k)
    legend += (legend.empty() ? "" : ", ") + std::to_string(k + 1) + " " + cases[k].name;
  figure.notes.push_back("cases: " + legend);
  figure.marked_meaning = "diverged (value at the step it stopped) or error";
  figure.columns = 2;
  struct Metric {
    std::string title, y_label;
    double StabilityRow::*value;
    double scale;
  };
  // Strain in percent, as on the console and in report.md.
  const std::vector<Metric> metrics = {
      {"max edge strain (a rollout stops above 300 %)", "max edge strain [%] (100 (|e|/h - 1))",
       &StabilityRow::max_strain, 100.0},
      {"energy growth (1 = the Newton reference)", "energy growth", &StabilityRow::energy_growth, 1.0}};
  for (const Metric& metric : metrics) {
    PlotPanel panel;
    panel.title = metric.title;
    panel.x_label = "case number (see the list above)";
    panel.y_label = metric.y_label;
    panel.log_x = false;
    panel.log_y = true;
    for (const std::string& method : methods) {
      PlotSeries series;
      series.name = method;
      for (std::size_t k = 0; k < cases.size(); ++k)
        for (const StabilityRow& r : rows)
          if (r.method == method && r.case_name == cases[k].name)
            series.points.push_back({static_cast<double>(k + 1), metric.scale * (r.*metric.value), "",
                                     r.outcome != StabilityOutcome::Finished});
      if (!series.points.empty()) panel.series.push_back(series);
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace fnopt
