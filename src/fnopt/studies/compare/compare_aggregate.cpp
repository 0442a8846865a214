#include <fnopt/studies/compare/compare_aggregate.hpp>

#include <algorithm>

#include <fnopt/io/csv_table.hpp>

namespace fnopt {

Aggregate aggregate(const std::vector<RunResult>& results, const std::string& res, const std::string& method,
                    int budget, int threads) {
  Aggregate a;
  std::vector<double> ms, cd, e3d, step;
  for (const auto& r : results) {
    if (r.resolution != res || r.spec.method != method || r.spec.budget != budget) continue;
    ++a.runs;
    a.diverged += r.diverged;
    a.failed += r.failed;
    if ((r.diverged || r.failed) && a.note.empty()) a.note = r.note;
    ms.push_back(plotted_ms(r, threads));
    cd.push_back(r.e_cd);
    e3d.push_back(r.e_3d);
    step.push_back(r.step_median);
  }
  a.ms = mean_finite(ms);
  a.e_cd = mean_finite(cd);
  a.e_3d = mean_finite(e3d);
  a.step = mean_finite(step);
  return a;
}

std::string report_number(double value, int digits) {
  return std::isfinite(value) ? CsvTable::number(value, digits) : "–";
}

std::string diverged_text(const Aggregate& a) {
  if (a.runs == 0) return "";
  std::string text = a.failed ? "error" : (a.diverged ? "yes" : "no");
  if (a.runs > 1 && (a.failed || a.diverged))
    text += " (" + std::to_string(a.diverged + a.failed) + " of " + std::to_string(a.runs) + ")";
  if (!a.note.empty()) text += ": " + a.note;
  return text;
}

std::vector<int> budgets_of(const std::vector<RunResult>& results, const std::string& method) {
  std::vector<int> budgets;
  for (const auto& r : results)
    if (r.spec.method == method && std::find(budgets.begin(), budgets.end(), r.spec.budget) == budgets.end())
      budgets.push_back(r.spec.budget);
  std::sort(budgets.begin(), budgets.end());
  return budgets;
}

}  // namespace fnopt
