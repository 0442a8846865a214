// fnopt repulsion-study: self-repulsion off and on, on the handle presets whose cloth folds onto
// itself (corner-center, single-mid-edge) and on the corner control (the paper's Table 6.5).
// Writes DIR/repulsion.csv, DIR/repulsion.svg (repulsive energy over time) and DIR/report.md.
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <sstream>

#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/threads.hpp"
#include "io/csv_table.hpp"
#include "io/markdown_report.hpp"
#include "io/svg_plot.hpp"
#include "metrics/self_contact.hpp"
#include "simulation/rollout.hpp"
#include "util/error.hpp"
#include "util/output_path.hpp"
#include "util/parse_text.hpp"
#include "util/progress_bar.hpp"

namespace fnopt::app {
namespace {

namespace fs = std::filesystem;

const char* const kPresets[] = {"corner-center", "single-mid-edge", "corner"};

struct StudyFlags {
  std::string out;
  std::string optimizers = "newton,fnopt-ls";
  int frames = 390;
  int res = 32;
  std::string motion = "xy_v2";
  double stiffness = Material{}.repulsion_stiffness;
  int iterations = 0;
  std::string model;
  int threads = 0;  // the default: set_thread_count
};

struct StudyRun {
  std::string preset, optimizer;
  bool repulsion = false;
  RolloutResult rollout;
  std::vector<SelfContactFrame> frames;
  SelfContactSummary summary;
  int converged = 0;
  bool tolerance = false;  // the method runs to a tolerance (converged steps are meaningful)
};

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


const std::vector<std::string>& csv_columns() {
  static const std::vector<std::string> columns = {
      "preset", "repulsion", "optimizer", "res", "frames", "frames_done", "ms_per_frame", "iterations_per_step",
      "converged_steps", "mean_energy_J", "max_energy_J", "share_above_1e-5J", "share_above_1e-4J",
      "share_above_1e-3J", "max_pairs_half_delta", "max_pairs_quarter_delta", "share_frames_quarter_delta",
      "min_distance_over_delta", "max_strain_pct", "diverged"};
  return columns;
}

std::vector<std::string> csv_row(const StudyRun& r, const StudyFlags& flags) {
  const auto& s = r.summary;
  const int steps = static_cast<int>(r.rollout.steps.size());
  return {r.preset,
          r.repulsion ? "on" : "off",
          r.optimizer,
          std::to_string(flags.res),
          std::to_string(flags.frames),
          std::to_string(static_cast<int>(r.rollout.positions.size()) - 1),
          CsvTable::number(r.rollout.mean_step_ms(), 4),
          CsvTable::number(steps ? static_cast<double>(r.rollout.total_iterations()) / steps : 0.0, 4),
          r.tolerance ? std::to_string(r.converged) + "/" + std::to_string(steps) : "budget",
          CsvTable::number(s.mean_energy, 4),
          CsvTable::number(s.max_energy, 4),
          CsvTable::number(s.share_above[0], 4),
          CsvTable::number(s.share_above[1], 4),
          CsvTable::number(s.share_above[2], 4),
          std::to_string(s.max_pairs_half),
          std::to_string(s.max_pairs_quarter),
          CsvTable::number(s.frames_with_quarter, 4),
          CsvTable::number(s.min_distance, 4),
          CsvTable::number(100.0 * r.rollout.max_strain(), 4),
          r.rollout.diverged ? "yes" : "no"};
}

// The printed / Markdown table: the columns a reader compares.
std::vector<std::string> table_header() {
  return {"preset", "repulsion", "optimizer", "ms/frame", "it/step", "mean E_rep [J]", "E>1e-5", "E>1e-4",
          "E>1e-3", "max #<δ/2", "max #<δ/4", "frames #<δ/4", "min d/δ", "strain", "status"};
}

std::vector<std::string> table_row(const StudyRun& r) {
  const auto& s = r.summary;
  const int steps = static_cast<int>(r.rollout.steps.size());
  auto percent = [](double share) { return fixed(100.0 * share, 0) + "%"; };
  std::string status = r.rollout.diverged ? "diverged" : "finite";
  if (r.tolerance) status += ", " + std::to_string(r.converged) + "/" + std::to_string(steps) + " conv";
  return {r.preset,
          r.repulsion ? "on" : "off",
          r.optimizer,
          fixed(r.rollout.mean_step_ms(), 1),
          fixed(steps ? static_cast<double>(r.rollout.total_iterations()) / steps : 0.0, 1),
          sci(s.mean_energy),
          percent(s.share_above[0]),
          percent(s.share_above[1]),
          percent(s.share_above[2]),
          std::to_string(s.max_pairs_half),
          std::to_string(s.max_pairs_quarter),
          percent(s.frames_with_quarter),
          fixed(s.min_distance, 2),
          fixed(100.0 * r.rollout.max_strain(), 0) + "%",
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

PlotFigure make_plot(const std::vector<StudyRun>& runs, const StudyFlags& flags) {
  PlotFigure figure;
  figure.title = "Self-contact: repulsive energy per frame (lambda_ref = 1 N/m, delta = h)";
  figure.notes = {std::to_string(flags.res) + "x" + std::to_string(flags.res) + " grid, motion " + flags.motion +
                      ", " + std::to_string(flags.frames) + " frames; repulsion on: lambda = " +
                      sci(flags.stiffness) + " N/m",
                  "frames with zero energy (no pair within delta) cannot be drawn on the log axis"};
  figure.columns = 3;
  figure.marked_meaning = "";
  for (const char* preset : kPresets) {
    PlotPanel panel;
    panel.title = std::string(preset) + (std::string(preset) == "corner" ? " (control)" : "");
    panel.x_label = "time [s]";
    panel.y_label = "repulsive energy [J]";
    panel.log_x = false;
    panel.log_y = true;
    for (const auto& r : runs) {
      if (r.preset != preset) continue;
      PlotSeries series;
      series.name = r.optimizer + ", repulsion " + (r.repulsion ? "on" : "off");
      for (std::size_t t = 0; t < r.frames.size(); ++t) series.points.push_back({r.rollout.times[t], r.frames[t].energy, "", false});
      panel.series.push_back(series);
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

void run_study(const StudyFlags& flags) {
  require(!flags.out.empty(), "out", "an output directory is required");
  require(flags.frames >= 1, "frames", "must be at least 1");
  require(flags.res >= 3, "res", "the grid needs at least 3 vertices along each side");
  const std::vector<std::string> optimizers = name_list("optimizers", flags.optimizers);
  std::vector<OptimizerChoice> choices;
  for (const auto& name : optimizers) {  // fail on a bad name before any work
    OptimizerChoice choice;
    choice.name = name;
    choice.iterations = flags.iterations;
    choice.model = flags.model;
    choice.make();
    choices.push_back(choice);
  }
  Scene base;
  base.rows = base.cols = flags.res;
  base.frames = flags.frames;
  apply_scene_setting(base, "motion", flags.motion);
  apply_scene_setting(base, "repulsion-stiffness", number_text(flags.stiffness));
  base.validate();
  require_writable_directory(flags.out, "out");
  const int threads = set_thread_count(flags.threads);
  std::fprintf(stderr,
               "fnopt repulsion-study: %dx%d grid, motion %s, %d frames, presets corner-center, single-mid-edge, "
               "corner; repulsion off/on (lambda %.4g N/m, delta = h); optimizers %s; %d thread%s\n",
               flags.res, flags.res, flags.motion.c_str(), flags.frames, flags.stiffness, flags.optimizers.c_str(),
               threads, threads == 1 ? "" : "s");

  const int run_count = static_cast<int>(std::size(kPresets) * 2 * choices.size());
  ProgressBar bar("repulsion-study", run_count * flags.frames);
  CsvTable csv(csv_columns());
  const std::string csv_path = (fs::path(flags.out) / "repulsion.csv").string();
  std::vector<StudyRun> runs;
  int done_before = 0;
  for (const char* preset : kPresets)
    for (bool repulsion : {false, true})
      for (const auto& choice : choices) {
        Scene scene = base;
        apply_scene_setting(scene, "handles", preset);
        apply_scene_setting(scene, "repulsion", repulsion ? "true" : "false");
        StudyRun run;
        run.preset = preset;
        run.optimizer = choice.name;
        run.repulsion = repulsion;
        const auto optimizer = choice.make();
        RolloutOptions options;
        options.solve = choice.solve_options();
        run.tolerance = options.solve.relative_tolerance > 0.0;
        const std::string label = std::string(preset) + (repulsion ? " on " : " off ") + choice.name;
        run.rollout = run_rollout(resolve(scene), *optimizer, options, [&](int done, int, const StepRecord& s) {
          char status[128];
          std::snprintf(status, sizeof status, "%s: %.1f ms/step, %d it", label.c_str(), s.wall_ms, s.iterations);
          bar.update(done_before + done, status);
        });
        done_before += flags.frames;
        SpatialHash hash;
        VecX x;
        for (const auto& positions : run.rollout.positions) {
          x = positions.cast<double>();
          run.frames.push_back(measure_self_contact(run.rollout.grid, x, hash));
        }
        run.summary = summarize_self_contact(run.frames);
        run.converged = run.rollout.converged_steps();
        csv.add_row(csv_row(run, flags));
        csv.write(csv_path);  // finished rows survive an interrupted study
        runs.push_back(std::move(run));
      }
  bar.finish();

  std::vector<std::vector<std::string>> rows;
  for (const auto& r : runs) rows.push_back(table_row(r));
  const std::string svg_name = "repulsion.svg";
  write_svg((fs::path(flags.out) / svg_name).string(), make_plot(runs, flags));

  std::ostringstream command;
  command << "fnopt repulsion-study --out " << flags.out << " --optimizers " << flags.optimizers << " --frames "
          << flags.frames << " --res " << flags.res << " --motion " << flags.motion << " --repulsion-stiffness "
          << number_text(flags.stiffness) << " --threads " << threads;
  MarkdownReport report("Self-repulsion study");
  report.paragraph("Handle presets whose cloth folds onto itself (corner-center, single-mid-edge) and the corner "
                   "control, each simulated with self-repulsion off and on (lambda = " +
                   sci(flags.stiffness) + " N/m, delta = h), " + std::to_string(flags.res) + "x" +
                   std::to_string(flags.res) + " grid, motion " + flags.motion + ", " +
                   std::to_string(flags.frames) + " frames at dt = 1/60 s, " + std::to_string(threads) +
                   " thread(s).");
  report.bullets({"E_rep: the repulsive energy of each frame's configuration under the same barrier with a fixed "
                  "reference lambda_ref = 1 N/m and delta = h (metrics/self_contact.hpp), averaged over frames.",
                  "E>1e-5 / 1e-4 / 1e-3: share of frames whose E_rep exceeds 1e-5 J (the cloth touches itself), "
                  "1e-4 J (pressed contact; one pair at delta/2 is 1.7e-4 J at 32x32), 1e-3 J (deep contact).",
                  "max #<δ/2, #<δ/4: the most non-adjacent vertex pairs closer than delta/2, delta/4 in any "
                  "frame (penetration proxies); frames #<δ/4: share of frames with such a pair; min d/δ: the "
                  "smallest pair distance in any frame."});
  report.table(table_header(), rows);
  report.image(svg_name, "repulsive energy over time");
  report.paragraph("Every column of every run: repulsion.csv.");
  report.code(command.str());
  report.write((fs::path(flags.out) / "report.md").string());

  print_table(table_header(), rows);
  std::printf("wrote %s, %s/%s and %s/report.md (%d thread%s)\n", csv_path.c_str(), flags.out.c_str(),
              svg_name.c_str(), flags.out.c_str(), threads, threads == 1 ? "" : "s");
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<StudyFlags>();
  CLI::App* command = app.add_subcommand(
      "repulsion-study",
      "self-repulsion off and on for the folding presets (corner-center, single-mid-edge) and the corner control: "
      "repulsive energy and penetration proxies per rollout (CSV, SVG, report)");
  command->add_option("--out", flags->out, "output directory (repulsion.csv, repulsion.svg, report.md)")->required();
  command->add_option("--optimizers", flags->optimizers, "optimizers, comma-separated: " + optimizer_names())
      ->capture_default_str();
  command->add_option("--frames", flags->frames, "time steps per rollout")->capture_default_str();
  command->add_option("--res", flags->res, "grid resolution N (N x N)")->capture_default_str();
  command->add_option("--motion", flags->motion, "handle motion")->capture_default_str();
  command->add_option("--repulsion-stiffness", flags->stiffness, "lambda of the runs with repulsion on [N/m]")
      ->capture_default_str();
  command->add_option("--iters", flags->iterations, "iterations per step (default: each method's)");
  command->add_option("--model", flags->model, "learned optimizer weights (default: the shipped model)");
  add_threads_flag(*command, flags->threads);
  command->callback([flags] { run_study(*flags); });
});

}  // namespace
}  // namespace fnopt::app
