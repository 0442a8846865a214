#include <fnopt/studies/repulsion/repulsion_report.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <fnopt/io/markdown_report.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

namespace fs = std::filesystem;

const std::vector<std::string>& repulsion_run_columns() {
  static const std::vector<std::string> columns = {"preset",
                                                   "repulsion",
                                                   "optimizer",
                                                   "res",
                                                   "frames",
                                                   "frames_done",
                                                   "ms_per_frame",
                                                   "iterations_per_step",
                                                   "converged_steps",
                                                   "mean_energy_J",
                                                   "max_energy_J",
                                                   "share_above_1e-5J",
                                                   "share_above_1e-4J",
                                                   "share_above_1e-3J",
                                                   "max_pairs_half_delta",
                                                   "max_pairs_quarter_delta",
                                                   "share_frames_quarter_delta",
                                                   "min_distance_over_delta",
                                                   "max_strain_pct",
                                                   "diverged"};
  return columns;
}

const std::vector<std::string>& repulsion_energy_columns() {
  static const std::vector<std::string> columns = {"preset", "repulsion", "optimizer", "time_s", "energy_J"};
  return columns;
}

namespace {

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string sci(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// The printed / Markdown table: the columns a reader compares, from a row of repulsion.csv.
std::vector<std::string> table_header() {
  return {"preset", "repulsion", "optimizer", "ms/frame",     "it/step", "mean E_rep [J]", "E>1e-5", "E>1e-4",
          "E>1e-3", "max #<δ/2", "max #<δ/4", "frames #<δ/4", "min d/δ", "strain",         "status"};
}

std::vector<std::string> table_row(const std::vector<std::string>& row) {
  std::map<std::string, std::string> cell;
  for (std::size_t c = 0; c < repulsion_run_columns().size(); ++c) cell[repulsion_run_columns()[c]] = row[c];
  auto number = [&](const std::string& column) {
    double value = 0.0;
    return parse_double(cell[column], value) ? value : NAN;
  };
  auto percent = [&](const std::string& column) { return fixed(100.0 * number(column), 0) + "%"; };
  std::string status = cell["diverged"] == "yes" ? "diverged" : "finite";
  if (cell["converged_steps"] != "budget") status += ", " + cell["converged_steps"] + " conv";
  return {cell["preset"],
          cell["repulsion"],
          cell["optimizer"],
          fixed(number("ms_per_frame"), 1),
          fixed(number("iterations_per_step"), 1),
          sci(number("mean_energy_J")),
          percent("share_above_1e-5J"),
          percent("share_above_1e-4J"),
          percent("share_above_1e-3J"),
          cell["max_pairs_half_delta"],
          cell["max_pairs_quarter_delta"],
          percent("share_frames_quarter_delta"),
          fixed(number("min_distance_over_delta"), 2),
          fixed(number("max_strain_pct"), 0) + "%",
          status};
}

void print_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width(header.size());
  auto length = [](const std::string& text) {  // code points, so δ counts once
    std::size_t n = 0;
    for (unsigned char c : text) n += (c & 0xC0) != 0x80;
    return n;
  };
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = length(header[c]);
    for (const auto& row : rows) width[c] = std::max(width[c], length(row[c]));
  }
  auto print_row = [&](const std::vector<std::string>& row) {
    for (std::size_t c = 0; c < row.size(); ++c)
      std::printf("%s%s%s", c ? "  " : "", std::string(width[c] - length(row[c]), ' ').c_str(), row[c].c_str());
    std::printf("\n");
  };
  print_row(header);
  for (const auto& row : rows) print_row(row);
}

PlotFigure make_plot(const std::vector<std::vector<std::string>>& energy_rows, const RepulsionStudy& study) {
  PlotFigure figure;
  figure.title = "Self-contact: repulsive energy per frame (lambda_ref = 1 N/m, delta = h)";
  figure.notes = {std::to_string(study.base.rows) + "x" + std::to_string(study.base.cols) + " grid, motion " +
                      study.base.motion + ", " + std::to_string(study.base.frames) +
                      " frames; repulsion on: lambda = " + sci(study.base.material.repulsion_stiffness) + " N/m",
                  "frames with zero energy (no pair within delta) cannot be drawn on the log axis"};
  figure.columns = 3;
  figure.marked_meaning = "";
  for (const std::string& preset : repulsion_presets()) {
    PlotPanel panel;
    panel.title = preset + (preset == "corner" ? " (control)" : "");
    panel.x_label = "time [s]";
    panel.y_label = "repulsive energy [J]";
    panel.log_x = false;
    panel.log_y = true;
    for (const auto& row : energy_rows) {  // rows of one run are consecutive
      if (row[0] != preset) continue;
      const std::string name = row[2] + ", repulsion " + row[1];
      if (panel.series.empty() || panel.series.back().name != name) panel.series.push_back({name, {}});
      double time = 0.0, energy = 0.0;
      if (parse_double(row[3], time) && parse_double(row[4], energy))
        panel.series.back().points.push_back({time, energy, "", false});
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace

void write_repulsion_report(const RepulsionStudy& study, const std::vector<std::vector<std::string>>& runs,
                            const std::vector<std::vector<std::string>>& energy) {
  const Scene& base = study.base;
  const std::string csv_path = (fs::path(study.out) / "repulsion.csv").string();
  const std::string energy_path = (fs::path(study.out) / "repulsion_energy.csv").string();
  std::vector<std::vector<std::string>> table_rows;
  for (const auto& row : runs) table_rows.push_back(table_row(row));
  const std::string svg_name = "repulsion.svg";
  write_svg((fs::path(study.out) / svg_name).string(), make_plot(energy, study));

  MarkdownReport report("Self-repulsion study");
  report.paragraph(
      "Handle presets whose cloth folds onto itself (corner-center, single-mid-edge) and the corner "
      "control, each simulated with self-repulsion off and on (lambda = " +
      sci(base.material.repulsion_stiffness) + " N/m, delta = h), " + std::to_string(base.rows) + "x" +
      std::to_string(base.cols) + " grid, motion " + base.motion + ", " + std::to_string(base.frames) +
      " frames at dt = " + number_text(base.dt) + " s, " + std::to_string(study.threads) + " thread(s).");
  report.bullets(
      {"E_rep: the repulsive energy of each frame's configuration under the same barrier with a fixed "
       "reference lambda_ref = 1 N/m and delta = h (metrics/self_contact.hpp), averaged over frames.",
       "E>1e-5 / 1e-4 / 1e-3: share of frames whose E_rep exceeds 1e-5 J (the cloth touches itself), "
       "1e-4 J (pressed contact; one pair at delta/2 is 1.7e-4 J at 32x32), 1e-3 J (deep contact).",
       "max #<δ/2, #<δ/4: the most non-adjacent vertex pairs closer than delta/2, delta/4 in any "
       "frame (penetration proxies); frames #<δ/4: share of frames with such a pair; min d/δ: the "
       "smallest pair distance in any frame."});
  report.table(table_header(), table_rows);
  report.image(svg_name, "repulsive energy over time");
  report.paragraph("Every column of every run: repulsion.csv; the energy of every frame: repulsion_energy.csv.");
  report.code(study.command_line);
  report.write((fs::path(study.out) / "report.md").string());

  print_table(table_header(), table_rows);
  std::printf("wrote %s, %s, %s/%s and %s/report.md (%d thread%s)\n", csv_path.c_str(), energy_path.c_str(),
              study.out.c_str(), svg_name.c_str(), study.out.c_str(), study.threads, study.threads == 1 ? "" : "s");
}

}  // namespace fnopt
