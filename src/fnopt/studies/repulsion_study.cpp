#include <fnopt/studies/repulsion_study.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/markdown_report.hpp>
#include <fnopt/io/svg_plot.hpp>
#include <fnopt/metrics/self_contact.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/studies/resumed_rows.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

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

const std::vector<std::string>& run_columns() {
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

const std::vector<std::string>& energy_columns() {
  static const std::vector<std::string> columns = {"preset", "repulsion", "optimizer", "time_s", "energy_J"};
  return columns;
}

const std::vector<std::string> kKeyColumns = {"preset", "repulsion", "optimizer"};

// One finished run: its row of repulsion.csv and the energy of each of its frames.
struct RunResult {
  std::vector<std::string> row;
  std::vector<std::pair<double, double>> energy;  // (time [s], repulsive energy [J])
};

RunResult run_one(const Scene& base, const std::string& preset, bool repulsion, const OptimizerChoice& choice,
                  const StepCallback& on_step) {
  Scene scene = base;
  apply_scene_setting(scene, "handles", preset);
  apply_scene_setting(scene, "repulsion", repulsion ? "true" : "false");
  const auto optimizer = choice.make();
  RolloutOptions options;
  options.solve = choice.solve_options();
  const bool tolerance = options.solve.to_tolerance();
  const RolloutResult rollout = run_rollout(resolve(scene), *optimizer, options, on_step);

  RunResult result;
  std::vector<SelfContactFrame> frames;
  SpatialHash hash;
  VecX x;
  for (std::size_t t = 0; t < rollout.positions.size(); ++t) {
    x = rollout.positions[t].cast<double>();
    frames.push_back(measure_self_contact(rollout.grid, x, hash));
    result.energy.emplace_back(rollout.times[t], frames.back().energy);
  }
  const SelfContactSummary s = summarize_self_contact(frames);
  const int steps = static_cast<int>(rollout.steps.size());
  result.row = {preset,
                repulsion ? "on" : "off",
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

// The printed / Markdown table: the columns a reader compares, from a row of repulsion.csv.
std::vector<std::string> table_header() {
  return {"preset", "repulsion", "optimizer", "ms/frame",     "it/step", "mean E_rep [J]", "E>1e-5", "E>1e-4",
          "E>1e-3", "max #<δ/2", "max #<δ/4", "frames #<δ/4", "min d/δ", "strain",         "status"};
}

std::vector<std::string> table_row(const std::vector<std::string>& row) {
  std::map<std::string, std::string> cell;
  for (std::size_t c = 0; c < run_columns().size(); ++c) cell[run_columns()[c]] = row[c];
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

const std::vector<std::string>& repulsion_presets() {
  static const std::vector<std::string> presets = {"corner-center", "single-mid-edge", "corner"};
  return presets;
}

void run_repulsion_study(const RepulsionStudy& study) {
  const Scene& base = study.base;
  const std::string csv_path = (fs::path(study.out) / "repulsion.csv").string();
  const std::string energy_path = (fs::path(study.out) / "repulsion_energy.csv").string();
  const ResumedRows resumed(csv_path, run_columns(), kKeyColumns, study.resume, "repulsion-study");
  // The energy rows of the runs kept, by run key (several rows per run: ResumedRows keeps one).
  std::map<std::string, std::vector<std::vector<std::string>>> kept_energy;
  if (resumed.size() > 0) {
    std::fprintf(stderr, "resuming: %zu finished runs in %s\n", resumed.size(), csv_path.c_str());
    require(fs::exists(energy_path), "resume", energy_path + " is missing: cannot redraw the finished runs");
    const CsvTable earlier = CsvTable::read(energy_path);
    require(earlier.columns() == energy_columns(), "resume",
            energy_path + ": written by another version of repulsion-study: cannot resume");
    for (const auto& row : earlier.rows()) kept_energy[ResumedRows::key({row[0], row[1], row[2]})].push_back(row);
  }
  std::fprintf(stderr,
               "fnopt repulsion-study: %dx%d grid, motion %s, %d frames, presets corner-center, single-mid-edge, "
               "corner; repulsion off/on (lambda %.4g N/m, delta = h); %zu optimizer%s; %d thread%s\n",
               base.rows, base.cols, base.motion.c_str(), base.frames, base.material.repulsion_stiffness,
               study.optimizers.size(), study.optimizers.size() == 1 ? "" : "s", study.threads,
               study.threads == 1 ? "" : "s");

  // Progress in frame-cost units (methods/registry.hpp), as compare and stability count it.
  auto cost = [&](const OptimizerChoice& choice) {
    const InnerSolveOptions solve = choice.solve_options();
    return base.frames * frame_cost(choice.name, solve.max_iterations, solve.to_tolerance(), base.rows * base.cols);
  };
  double total_cost = 0.0, done_cost = 0.0;
  for (const std::string& preset : repulsion_presets())
    for (const char* repulsion : {"off", "on"})
      for (const auto& choice : study.optimizers) {
        total_cost += cost(choice);
        if (resumed.find(ResumedRows::key({preset, repulsion, choice.name}))) done_cost += cost(choice);
      }
  const double unit = std::max(1.0, total_cost / 1e6);  // at most ~1e6 units: fits an int
  ProgressBar bar("repulsion-study", static_cast<int>(total_cost / unit), static_cast<int>(done_cost / unit));

  CsvTable runs(run_columns()), energy(energy_columns());
  // Runs of the earlier files that this plan does not name (other optimizers) stay in them, as
  // in compare and stability: resuming with a subset never drops finished work.
  std::set<std::string> planned;
  for (const std::string& preset : repulsion_presets())
    for (const char* repulsion : {"off", "on"})
      for (const auto& choice : study.optimizers) planned.insert(ResumedRows::key({preset, repulsion, choice.name}));
  for (const auto& row : resumed.unplanned(planned)) {
    runs.add_row(row);
    for (const auto& energy_row : kept_energy[ResumedRows::key({row[0], row[1], row[2]})]) energy.add_row(energy_row);
  }
  std::vector<std::vector<std::string>> table_rows;
  for (const std::string& preset : repulsion_presets())
    for (bool repulsion : {false, true})
      for (const auto& choice : study.optimizers) {
        const std::string on_off = repulsion ? "on" : "off";
        const std::string key = ResumedRows::key({preset, on_off, choice.name});
        if (const auto* earlier = resumed.find(key)) {
          runs.add_row(*earlier);
          for (const auto& row : kept_energy[key]) energy.add_row(row);
          table_rows.push_back(table_row(*earlier));
          continue;
        }
        const std::string label = preset + " " + on_off + " " + choice.name;
        const double start = done_cost, weight = cost(choice) / base.frames;
        const RunResult result = run_one(base, preset, repulsion, choice, [&](int done, int, const StepRecord& s) {
          char status[128];
          std::snprintf(status, sizeof status, "%s: %.1f ms/step, %d it", label.c_str(), s.wall_ms, s.iterations);
          bar.update(static_cast<int>((start + done * weight) / unit), status);
        });
        done_cost = start + cost(choice);
        runs.add_row(result.row);
        for (const auto& [time, value] : result.energy)
          energy.add_row({preset, on_off, choice.name, CsvTable::number(time, 8), CsvTable::number(value, 6)});
        table_rows.push_back(table_row(result.row));
        energy.write(energy_path);  // both files hold every finished run: an interrupted study resumes
        runs.write(csv_path);
      }
  bar.finish();

  const std::string svg_name = "repulsion.svg";
  write_svg((fs::path(study.out) / svg_name).string(), make_plot(energy.rows(), study));

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
