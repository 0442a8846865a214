#pragma once
// What `fnopt compare` reports besides its CSV: the error-time plot (compare.svg), the
// zero-shot super-resolution plot (superres.svg: error and ms/frame against vertex count, the
// learned optimizer run on each grid against the same optimizer solving at 32^2 and
// interpolating), and DIR/report.md tying them together. Written by studies/compare/compare_outputs.cpp.
#include <string>
#include <vector>

#include <fnopt/studies/compare/compare_frontier.hpp>
#include <fnopt/studies/compare/compare_plot.hpp>
#include <fnopt/studies/compare/compare_run_result.hpp>

namespace fnopt {

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
