#include <fnopt/studies/stability/stability_table.hpp>

#include <cmath>
#include <cstdio>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

double number_or_nan(const std::string& text) {
  double value = NAN;
  return parse_double(text, value) ? value : NAN;
}

}  // namespace

std::string stability_cell(double value, int digits) {
  return std::isfinite(value) ? CsvTable::number(value, digits) : "";
}

const std::vector<std::string>& stability_columns() {
  static const std::vector<std::string> columns = {"case",
                                                   "method",
                                                   "N",
                                                   "outcome",
                                                   "frames",
                                                   "diverged_step",
                                                   "max_strain_pct",
                                                   "energy_growth",
                                                   "e_3d_x1e2",
                                                   "ms_per_frame",
                                                   "iterations_per_frame",
                                                   "unconverged_steps",
                                                   "unconverged_statuses",
                                                   "self_intersections",
                                                   "mesh_intersections",
                                                   "reason"};
  return columns;
}

std::string budget_text(const InnerSolveOptions& solve) {
  const std::string max = " (max " + std::to_string(solve.max_iterations) + ")";
  if (solve.acceleration_tolerance > 0.0) return "tol " + number_text(solve.acceleration_tolerance) + " m/s^2" + max;
  if (solve.relative_tolerance > 0.0) return "tol " + number_text(solve.relative_tolerance) + max;
  return std::to_string(solve.max_iterations);
}

std::vector<std::string> stability_csv_row(const StabilityRow& r) {
  const bool ran = r.outcome != StabilityOutcome::Error;
  return {r.case_name,
          r.method,
          budget_text(r.solve),
          to_string(r.outcome),
          std::to_string(r.frames_done) + "/" + std::to_string(r.frames_requested),
          r.diverged_step > 0 ? std::to_string(r.diverged_step) : "",
          stability_cell(100.0 * r.max_strain),
          stability_cell(r.energy_growth),
          stability_cell(1e2 * r.e3d),
          stability_cell(r.ms_per_frame),
          stability_cell(r.iterations_per_frame),
          ran ? std::to_string(r.unconverged_steps) : "",
          r.unconverged_statuses,
          r.self_intersections >= 0 ? std::to_string(r.self_intersections) : "",
          r.mesh_intersections >= 0 ? std::to_string(r.mesh_intersections) : "",
          r.reason};
}

StabilityRow stability_row_from_csv(const std::vector<std::string>& cells) {
  require(
      cells.size() == stability_columns().size(), "stability.csv",
      "a row has " + std::to_string(cells.size()) + " cells, expected " + std::to_string(stability_columns().size()));
  StabilityRow r;
  r.case_name = cells[0];
  r.method = cells[1];
  // "N": "100", "tol 1e-06 m/s^2 (max 200)" or "tol 1e-09 (max 1000)" (relative)
  if (cells[2].rfind("tol ", 0) == 0) {
    const auto open = cells[2].find("(max ");
    const auto unit = cells[2].find(" m/s^2");
    const auto end = std::min(open == std::string::npos ? cells[2].size() : open - 1, unit);
    (unit == std::string::npos ? r.solve.relative_tolerance : r.solve.acceleration_tolerance) =
        number_or_nan(cells[2].substr(4, end - 4));
    if (open != std::string::npos)
      parse_int(cells[2].substr(open + 5, cells[2].size() - open - 6), r.solve.max_iterations);
  } else {
    parse_int(cells[2], r.solve.max_iterations);
  }
  r.outcome = cells[3] == "finished"   ? StabilityOutcome::Finished
              : cells[3] == "diverged" ? StabilityOutcome::Diverged
                                       : StabilityOutcome::Error;
  const auto frames = split(cells[4], '/');
  if (frames.size() == 2) parse_int(frames[0], r.frames_done), parse_int(frames[1], r.frames_requested);
  if (!cells[5].empty()) parse_int(cells[5], r.diverged_step);
  r.max_strain = 1e-2 * number_or_nan(cells[6]);
  r.energy_growth = number_or_nan(cells[7]);
  r.e3d = 1e-2 * number_or_nan(cells[8]);
  r.ms_per_frame = number_or_nan(cells[9]);
  r.iterations_per_frame = number_or_nan(cells[10]);
  if (!cells[11].empty()) parse_int(cells[11], r.unconverged_steps);
  r.unconverged_statuses = cells[12];
  if (!cells[13].empty()) parse_int(cells[13], r.self_intersections);
  if (!cells[14].empty()) parse_int(cells[14], r.mesh_intersections);
  r.reason = cells[15];
  return r;
}

}  // namespace fnopt
