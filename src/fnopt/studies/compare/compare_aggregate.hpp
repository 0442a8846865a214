#pragma once
// compare's per-resolution summaries for report.md: one method and budget averaged over the
// motions it ran, and how its table cells read.
#include <cmath>
#include <string>
#include <vector>

#include <fnopt/studies/compare/compare_run_result.hpp>

namespace fnopt {

// One method and budget at one resolution, averaged over the motions it ran.
struct Aggregate {
  int runs = 0, diverged = 0, failed = 0;
  double ms = NAN, e_cd = NAN, e_3d = NAN;
  double step = NAN;  // the per-step error's median over each run's reference states
  std::string note;  // the first run's note if it diverged or failed
};

Aggregate aggregate(const std::vector<RunResult>& results, const std::string& res, const std::string& method,
                    int budget, int threads);
// "no", "yes (2 of 3): <note>", "error: <note>"; "" without runs.
std::string diverged_text(const Aggregate& a);
// A table cell: the value to `digits` significant digits, "–" if it is not finite.
std::string report_number(double value, int digits = 3);
// Budgets that `method` ran with, in increasing order.
std::vector<int> budgets_of(const std::vector<RunResult>& results, const std::string& method);

}  // namespace fnopt
