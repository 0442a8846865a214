#pragma once
// What `fnopt compare` reports besides its CSV: the error-time plot (compare.svg), the
// zero-shot super-resolution plot (superres.svg: error and ms/frame against vertex count, the
// learned optimizer run on each grid against the same optimizer solving at 32^2 and
// interpolating), and DIR/report.md tying them together. Used by studies/compare_study.cpp.
#include <cmath>
#include <string>
#include <vector>

#include <fnopt/io/svg_plot.hpp>

namespace fnopt {

struct RunSpec {
  std::string method;
  int budget = 0;  // 0: a method that runs to its tolerance (newton), run so
};

struct RunResult {
  RunSpec spec;
  std::string resolution, motion;  // "32" (32 x 32) or "32x64" (rows x cols)
  double lr = 0.0;
  double ms = NAN, cpu_share = NAN, iterations = NAN, e_cd = NAN, e_3d = NAN, step_mean = NAN, step_median = NAN,
         strain = NAN;
  double e_cd_arcsim = NAN;
  bool diverged = false, failed = false;
  int frames = 0, frames_requested = 0;
  std::string lr_source;  // where the learning rate came from (given, swept)
  bool frontier = false;  // Pareto-optimal in ms/frame and e_CD among its scene's runs
  std::string note;
};

// Newton to its reference tolerance (not a budgeted Newton run).
bool is_converged_run(const RunSpec& spec);
// "10", or "converged" for a converged run (the CSV's N).
std::string budget_text(const RunSpec& spec);
// The run time a plot or report shows: with one thread, wall time x the CPU share the process
// got (what it would take on an idle core of this shared machine); otherwise wall time.
double plotted_ms(const RunResult& r, int threads);
double mean_finite(const std::vector<double>& values);
// Vertices of a resolution text ("32" -> 1024, "32x64" -> 2048); 0 if it is not one.
int vertex_count_of(const std::string& resolution);
// "32^2" or "32x64".
std::string resolution_title(const std::string& resolution);

// Which of the points (ms, error) are Pareto-optimal: no other point is at most as slow and at
// most as far, and better in one. Points with a non-finite coordinate are never optimal.
std::vector<bool> pareto_optimal(const std::vector<std::pair<double, double>>& points);
// Sets RunResult::frontier per scene (resolution and motion) over the runs that finished:
// Pareto-optimal in (plotted ms/frame, e_CD against Newton).
void mark_frontier(std::vector<RunResult>& results, int threads);

// The fastest run of a method at one resolution whose mean e_CD over the motions is at most a level.
struct LevelWinner {
  double level = 0.0;  // e_CD
  std::string method;  // empty if no method reaches the level
  int budget = 0;
  double ms = NAN, e_cd = NAN;
};
// Per level, over the method-budget pairs that ran every motion of `resolution` without diverging
// (the converged reference excluded: it is the error's zero).
std::vector<LevelWinner> fastest_within(const std::vector<RunResult>& results, const std::string& resolution,
                                        const std::vector<double>& levels, int threads);

// The error-time figure: one row of panels per resolution, one line per method.
PlotFigure make_compare_plot(const std::vector<RunResult>& results, const std::vector<std::string>& methods,
                             const std::vector<std::string>& resolutions, const std::vector<std::string>& motions,
                             int threads, const std::vector<std::string>& notes);

struct CompareReport {
  std::string directory;  // where report.md, compare.csv, compare.svg live
  std::string command_line;
  std::string scene_text;                // the resolved scene of the first resolution
  std::vector<std::string> resolutions;  // in the order run
  std::vector<std::string> motions;
  std::vector<std::string> methods;
  std::vector<std::string> notes;  // as on the plot
  int threads = 1;
  bool superres = false;             // write the super-resolution section and superres.svg
  std::string preset;                // "superres" or empty
  std::string status;                // e.g. "finished" or "in progress: 7 of 24 runs"
  std::vector<double> error_levels;  // e_CD levels of the "fastest within" table
};

// Writes DIR/report.md and, if report.superres and the results hold fnopt and an
// interpolation method, DIR/superres.svg. Safe to call after every run (partial results).
void write_compare_report(const CompareReport& report, const std::vector<RunResult>& results);

}  // namespace fnopt
