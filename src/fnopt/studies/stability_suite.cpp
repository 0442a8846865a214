#include <fnopt/studies/stability_suite.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include <fnopt/cloth/backward_euler.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// Frames that keep the base scene's simulated time at another time step.
int frames_for_dt(const Scene& base, double dt) {
  return std::max(1, static_cast<int>(std::lround(base.frames * base.dt / dt)));
}

StabilityCase material_case(const std::string& name, const std::string& what, double Material::*field,
                            const std::string& field_name, double factor) {
  return {name,
          what + " x" + number_text(factor) + " of the base scene's",
          {"material." + field_name},
          [field, factor](const Scene& base) {
            Scene s = base;
            s.material.*field *= factor;
            return s;
          }};
}

StabilityCase speed_case(double factor) {
  return {"speed-x" + number_text(factor),
          "handle speed x" + number_text(factor) + " (the motion played faster)",
          {"speed"},
          [factor](const Scene& base) {
            Scene s = base;
            s.speed *= factor;
            return s;
          }};
}

StabilityCase dt_case(int steps_per_second) {
  const double dt = 1.0 / steps_per_second;
  const std::string text = "1/" + std::to_string(steps_per_second);
  return {"dt-" + text,
          "dt = " + text + " s, frames scaled to keep the base scene's simulated time",
          {"dt", "frames"},
          [dt](const Scene& base) {
            Scene s = base;
            s.frames = frames_for_dt(base, dt);
            s.dt = dt;
            return s;
          }};
}

StabilityCase handles_case(const std::string& preset) {
  return {"handles-" + preset,
          "handle preset '" + preset + "' instead of the base scene's",
          {"handles"},
          [preset](const Scene& base) {
            Scene s = base;
            s.handles = preset;
            s.handle_vertices.clear();
            return s;
          }};
}

StabilityCase grid_case(int n, int frame_divisor) {
  return {"grid-" + std::to_string(n),
          std::to_string(n) + "x" + std::to_string(n) + " grid (same cloth), on the first 1/" +
              std::to_string(frame_divisor) + " of the base scene's frames (its cost)",
          {"rows", "cols", "frames"},
          [n, frame_divisor](const Scene& base) {
            Scene s = base;
            s.rows = s.cols = n;
            s.frames = std::max(1, base.frames / frame_divisor);
            return s;
          }};
}

std::string cell(double value, int digits = 4) { return std::isfinite(value) ? CsvTable::number(value, digits) : ""; }

double number_or_nan(const std::string& text) {
  double value = NAN;
  return parse_double(text, value) ? value : NAN;
}

}  // namespace

// ---- The cases -------------------------------------------------------------------------------

const std::vector<StabilityCase>& stability_cases() {
  static const std::vector<StabilityCase> cases = [] {
    std::vector<StabilityCase> c;
    c.push_back({"baseline",
                 "the base scene itself (default: 32^2, corner handles, xy_v2, default material, dt 1/60)",
                 {},
                 [](const Scene& base) { return base; }});
    for (double f : {10.0, 100.0, 1000.0})
      c.push_back(material_case("stretch-x" + number_text(f), "stretch stiffness", &Material::stretch, "stretch", f));
    c.push_back({"soft",
                 "very soft cloth: stretch and shear x0.1 of the base scene's",
                 {"material.stretch", "material.shear"},
                 [](const Scene& base) {
                   Scene s = base;
                   s.material.stretch *= 0.1;
                   s.material.shear *= 0.1;
                   return s;
                 }});
    c.push_back(material_case("bend-x100", "bending stiffness", &Material::bend, "bend", 100.0));
    c.push_back(material_case("bend-x0.01", "bending stiffness", &Material::bend, "bend", 0.01));
    for (double f : {1.2, 1.5, 2.0, 4.0}) c.push_back(speed_case(f));
    c.push_back(dt_case(24));
    c.push_back(dt_case(240));
    for (const char* preset : {"diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center"})
      c.push_back(handles_case(preset));
    c.push_back(grid_case(128, 5));
    c.push_back(grid_case(200, 10));
    return c;
  }();
  return cases;
}

std::vector<std::string> stability_case_names() {
  std::vector<std::string> names;
  for (const auto& c : stability_cases()) names.push_back(c.name);
  return names;
}

std::vector<StabilityCase> select_stability_cases(const std::string& list) {
  const std::string all(trim(list));
  require(!all.empty(), "cases", "is empty: give 'all' or case names (--list-cases)");
  if (all == "all") return stability_cases();
  std::vector<StabilityCase> chosen;
  for (auto piece : split(all, ',')) {
    const std::string name(trim(piece));
    const auto& cases = stability_cases();
    const auto found = std::find_if(cases.begin(), cases.end(), [&](const StabilityCase& c) { return c.name == name; });
    require(found != cases.end(), "cases",
            "unknown case '" + name + "' (choose from: " + joined(stability_case_names()) + ")");
    if (std::none_of(chosen.begin(), chosen.end(), [&](const StabilityCase& c) { return c.name == name; }))
      chosen.push_back(*found);
  }
  return chosen;
}

// ---- Running ---------------------------------------------------------------------------------

StabilityRun run_stability_rollout(const Scene& scene, const StabilityMethod& method, const OptimizerFactory& factory,
                                   const RolloutOptions& base_options, const StepCallback& on_step) {
  StabilityRun run;
  run.frames_requested = scene.frames;
  try {
    const ResolvedScene setup = resolve(scene);  // validates the scene
    {
      const BackwardEulerObjective objective(setup.grid, scene.material, scene.dt, scene.gravity);
      run.initial_energy = objective.potential(setup.grid.rest_positions());
    }
    const std::unique_ptr<InnerOptimizer> optimizer = factory(method.method);
    if (!optimizer) throw Error("optimizer", "the factory made no optimizer for '" + method.method + "'");
    RolloutOptions options = base_options;
    options.solve = method.solve;
    run.rollout = run_rollout(setup, *optimizer, options, on_step);
  } catch (const std::exception& e) {
    run.failed = true;
    run.error = e.what();
  }
  return run;
}

const char* to_string(StabilityOutcome outcome) {
  switch (outcome) {
    case StabilityOutcome::Finished:
      return "finished";
    case StabilityOutcome::Diverged:
      return "diverged";
    case StabilityOutcome::Error:
      return "error";
  }
  return "error";
}

int count_unconverged_steps(const RolloutResult& rollout, const InnerSolveOptions& solve, std::string& statuses) {
  std::map<SolveStatus, int> counts;
  for (const StepRecord& s : rollout.steps) {
    const bool normal = is_converged(s.status) || (!solve.to_tolerance() && s.status == SolveStatus::IterationBudget);
    if (!normal) ++counts[s.status];
  }
  statuses.clear();
  int total = 0;
  for (const auto& [status, count] : counts) {
    statuses += (statuses.empty() ? "" : ", ") + std::string(to_string(status)) + " x" + std::to_string(count);
    total += count;
  }
  return total;
}

namespace {

// max and min of E_0 and the finite step energies.
std::pair<double, double> energy_range(const StabilityRun& run) {
  double hi = run.initial_energy, lo = run.initial_energy;
  for (const StepRecord& s : run.rollout.steps)
    if (std::isfinite(s.energy)) hi = std::max(hi, s.energy), lo = std::min(lo, s.energy);
  return {hi, lo};
}

}  // namespace

double energy_growth(const StabilityRun& run, const StabilityRun& reference) {
  if (run.failed || reference.failed || !std::isfinite(run.initial_energy) ||
      !std::isfinite(reference.initial_energy) || reference.rollout.steps.empty())
    return NAN;
  const auto [ref_hi, ref_lo] = energy_range(reference);
  const auto [hi, lo] = energy_range(run);
  (void)lo;
  const double span = ref_hi - ref_lo;
  if (!(span > 0.0)) return NAN;
  const double growth = (hi - ref_lo) / span;
  return std::isfinite(growth) ? growth : NAN;
}

StabilityRow stability_row(const std::string& case_name, const StabilityMethod& method, const StabilityRun& run,
                           const StabilityRun* reference) {
  StabilityRow row;
  row.case_name = case_name;
  row.method = method.method;
  row.reference = method.reference;
  row.solve = method.solve;
  row.frames_requested = run.frames_requested;
  if (run.failed) {
    row.outcome = StabilityOutcome::Error;
    row.reason = run.error;
    return row;
  }
  const RolloutResult& r = run.rollout;
  row.outcome = r.diverged ? StabilityOutcome::Diverged : StabilityOutcome::Finished;
  row.frames_done = static_cast<int>(r.positions.size()) - 1;
  row.diverged_step = r.diverged ? static_cast<int>(r.steps.size()) : 0;
  row.reason = r.divergence;
  double strain = NAN;
  for (const StepRecord& s : r.steps)
    if (std::isfinite(s.max_strain)) strain = std::isnan(strain) ? s.max_strain : std::max(strain, s.max_strain);
  row.max_strain = strain;
  row.ms_per_frame = ms_per_frame(r);
  if (!r.steps.empty()) row.iterations_per_frame = static_cast<double>(r.total_iterations()) / r.steps.size();
  row.unconverged_steps = count_unconverged_steps(r, method.solve, row.unconverged_statuses);
  if (reference && !reference->failed && reference->rollout.positions.size() > 1) {
    row.energy_growth = energy_growth(run, *reference);
    if (r.positions.size() > 1 && r.grid.rows == reference->rollout.grid.rows &&
        r.grid.cols == reference->rollout.grid.cols) {
      TrajectoryComparisonOptions options;
      options.chamfer_enabled = false;
      const TrajectoryComparison c = compare_trajectories(frames_of(reference->rollout), frames_of(r), -1.0, options);
      if (std::isfinite(c.e3d)) row.e3d = c.e3d;
    }
  }
  return row;
}

// ---- Results ---------------------------------------------------------------------------------

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
          cell(100.0 * r.max_strain),
          cell(r.energy_growth),
          cell(1e2 * r.e3d),
          cell(r.ms_per_frame),
          cell(r.iterations_per_frame),
          ran ? std::to_string(r.unconverged_steps) : "",
          r.unconverged_statuses,
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
  r.reason = cells[13];
  return r;
}

std::string stability_console_table(const std::vector<StabilityRow>& rows) {
  const std::vector<std::string> header = {"case",     "method",   "N",      "outcome",  "frames",
                                           "strain %", "E growth", "e3D e2", "ms/frame", "unconverged"};
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
                     cell(1e2 * r.max_strain, 3), cell(r.energy_growth, 3), cell(1e2 * r.e3d, 3),
                     cell(r.ms_per_frame, 3), unconverged});
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
