#include <fnopt/studies/compare/compare_run_result.hpp>

#include <algorithm>

#include <fnopt/methods/registry.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {

bool is_converged_run(const RunSpec& spec) {
  return spec.budget == 0 && method_traits(spec.method).budget == BudgetKind::ToTolerance;
}

bool is_reference_run(const RunSpec& spec) { return is_converged_run(spec) && method_traits(spec.method).reference; }

std::string budget_text(const RunSpec& spec) {
  return is_converged_run(spec) ? "converged" : std::to_string(spec.budget);
}

double plotted_ms(const RunResult& r, int threads) {
  return threads == 1 && std::isfinite(r.cpu_share) ? r.ms * std::min(1.0, r.cpu_share) : r.ms;
}

double mean_finite(const std::vector<double>& values) {
  double sum = 0.0;
  int n = 0;
  for (double v : values)
    if (std::isfinite(v)) sum += v, ++n;
  return n ? sum / n : std::nan("");
}

int vertex_count_of(const std::string& resolution) {
  const auto x = resolution.find('x');
  int rows = 0, cols = 0;
  if (x == std::string::npos) {
    if (!parse_int(resolution, rows)) return 0;
    return rows * rows;
  }
  if (!parse_int(resolution.substr(0, x), rows) || !parse_int(resolution.substr(x + 1), cols)) return 0;
  return rows * cols;
}

std::string resolution_title(const std::string& resolution) {
  return resolution.find('x') == std::string::npos ? resolution + "^2" : resolution;
}

std::string method_label(const std::string& method, int budget) {
  return method + (is_converged_run({method, budget}) ? "" : " N=" + std::to_string(budget));
}

}  // namespace fnopt
