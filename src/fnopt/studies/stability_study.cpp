#include <fnopt/studies/stability_study.hpp>

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/io/markdown_report.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/parallel/sweep_schedule.hpp>
#include <fnopt/studies/resumed_rows.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/progress_bar.hpp>
#include <fnopt/version.hpp>

namespace fnopt {
namespace {

namespace fs = std::filesystem;

// Relative cost of one frame (methods/registry.hpp), for the progress bar's ETA only.
double frame_cost(const StabilityMethod& m, const Scene& scene) {
  return fnopt::frame_cost(m.method, m.solve.max_iterations, m.reference && m.solve.to_tolerance(),
                           scene.rows * scene.cols);
}

std::string row_key(const std::string& case_name, const std::string& method, const std::string& budget) {
  return ResumedRows::key({case_name, method, budget});
}

// Before a line on stderr: on a terminal the progress bar's line is cleared first.
void clear_bar_line() {
  if (::isatty(STDERR_FILENO)) std::fprintf(stderr, "\r\033[K");
}

void print_row(const StabilityRow& r) {
  clear_bar_line();
  std::fprintf(stderr, "%-22s %-9s %-20s %-8s %4d/%-4d strain %7.1f%%  growth %7.3g  e3D %7.3g  %8.2f ms/frame%s%s\n",
               r.case_name.c_str(), r.method.c_str(), budget_text(r.solve).c_str(), to_string(r.outcome), r.frames_done,
               r.frames_requested, 100 * r.max_strain, r.energy_growth, 100 * r.e3d, r.ms_per_frame,
               r.reason.empty() ? "" : "  ", r.reason.c_str());
}

struct Outputs {
  std::string dir, csv, svg, report;
};

void write_report(const Outputs& out, const StabilityStudy& study, const std::vector<StabilityRow>& rows,
                  const CsvTable& table, const std::string& started, bool complete) {
  const Scene& base = study.base;
  const auto& cases = study.cases;
  const auto& methods = study.methods;
  const auto& method_names = study.method_names;
  const int threads = study.threads;
  std::vector<std::string> notes = {std::to_string(base.frames) + " frames at dt = " + dt_text(base.dt) +
                                    " s on the base scene; " + std::to_string(threads) + " thread" +
                                    (threads == 1 ? "" : "s") +
                                    "; marked: diverged (strain > 300 % or non-finite) or error"};
  write_svg(out.svg, stability_plot(rows, cases, method_names, notes));

  MarkdownReport report("fnopt stability");
  report.paragraph(std::string(complete ? "" : "**Partial: the study is still running or was stopped.** ") +
                   "Stiff and extreme cases, every inner optimizer on each, against the case's Newton reference "
                   "(run to a residual acceleration of 1e-4 m/s^2 each step; steps that stop short are counted below). "
                   "fnopt " FNOPT_VERSION ", started " +
                   started + ", " + std::to_string(threads) + " thread" + (threads == 1 ? "" : "s") + ".");
  report.code(study.command_line);
  std::vector<std::string> setup = {
      "base scene: " + std::to_string(base.rows) + "x" + std::to_string(base.cols) + " grid, " +
      (base.handle_vertices.empty() ? base.handles : "explicit") + " handles, " +
      (base.trajectory.empty() ? "motion " + base.motion : "trajectory " + base.trajectory) + ", speed " +
      number_text(base.speed) + ", material " + base.material_name + " (stretch " + number_text(base.material.stretch) +
      " N/m, shear " + number_text(base.material.shear) + " N/m, bend " + number_text(base.material.bend) +
      " N m, density " + number_text(base.material.density) + " kg/m^2), dt " + dt_text(base.dt) + " s, " +
      std::to_string(base.frames) + " frames (" + number_text(base.frames * base.dt) + " s)"};
  std::string optimizers;
  for (const auto& m : methods)
    optimizers += (optimizers.empty() ? "" : ", ") + m.method + " (" +
                  (m.solve.to_tolerance() ? budget_text(m.solve) : "N=" + std::to_string(m.solve.max_iterations)) + ")";
  setup.push_back("optimizers (iterations per time step): " + optimizers +
                  "; gd and adam at their default learning rates (gd 1/lambda_max, adam 0.003)" +
                  (study.model.empty() ? "" : "; fnopt model " + study.model));
  report.bullets(setup);

  report.heading("Cases");
  std::vector<std::vector<std::string>> case_rows;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Scene s = cases[k].apply(base);
    // Every case scene was validated before any run: its grid exists.
    const GridUnitStiffness g =
        grid_unit_stiffness(Grid::make(s.rows, s.cols, s.size), s.material, s.dt, s.gravity.norm());
    const std::string k_text =
        CsvTable::number(g.stretch, 3) + " / " + CsvTable::number(g.shear, 3) + " / " + CsvTable::number(g.bend, 3);
    case_rows.push_back({std::to_string(k + 1), cases[k].name, cases[k].description,
                         std::to_string(s.rows) + "x" + std::to_string(s.cols),
                         std::to_string(s.frames) + " x " + dt_text(s.dt) + " s", k_text});
  }
  report.table({"#", "case", "what it changes", "grid", "frames", "k~ stretch / shear / bend (grid units)"}, case_rows);

  report.heading("What fails where");
  report.bullets(stability_summary(rows, method_names));

  report.heading("Results");
  report.paragraph(
      "One row per case and optimizer (also in stability.csv). outcome: finished, diverged (the rollout stops at "
      "the step whose edge strain exceeds 300 % or whose state is not finite; diverged_step and reason say where "
      "and why) or error (the optimizer or scene threw; the suite went on). max_strain: largest edge strain "
      "|e|/h - 1 over the finite steps. energy_growth: (max E - E_min)/(max E_ref - E_min), E the total energy "
      "(kinetic + potential) over the run including the rest state, E_ref the case's Newton reference and E_min "
      "its lowest energy: 1 for the reference, ~1 for a healthy run, >> 1 for a blow-up, < 1 for a run that "
      "loses energy. e_3d_x1e2: e_3D x 10^2 against the Newton reference of the same case, over the frames "
      "before a divergence. ms_per_frame: mean wall time of the inner solve after warm-up. "
      "unconverged_steps: steps that stopped for a reason other than convergence (for Newton every step short "
      "of its tolerance; for fixed-budget methods, reasons other than using the budget), with their "
      "SolveStatus.");
  report.table(table);
  report.image("stability.svg", "max edge strain and energy growth per case and optimizer");
  report.write(out.report);
}

}  // namespace

void run_stability_study(const StabilityStudy& study, const Communicator& comm) {
  const Scene& base = study.base;
  const auto& cases = study.cases;
  const auto& methods = study.methods;
  const auto& method_names = study.method_names;
  const int threads = study.threads;
  const OptimizerFactory factory = [&study](const std::string& method) {
    OptimizerChoice choice;
    choice.name = method;
    choice.model = study.model;
    return choice.make();
  };
  // The reference of every case: Newton at the suite's Newton settings.
  OptimizerChoice reference;
  reference.name = fnopt::reference_method();
  StabilityMethod reference_method{reference.name, reference.solve_options(), true};
  for (const auto& m : methods)
    if (m.reference) reference_method = m;

  const Outputs out{study.out, (fs::path(study.out) / "stability.csv").string(),
                    (fs::path(study.out) / "stability.svg").string(), (fs::path(study.out) / "report.md").string()};
  char started[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(started, sizeof started, "%Y-%m-%d %H:%M", std::localtime(&now));

  // --resume: rows of an earlier run with the same columns are kept and not run again.
  const ResumedRows resumed(out.csv, stability_columns(), {"case", "method", "N"}, study.resume, "stability");
  if (resumed.size() > 0 && comm.is_root())
    std::fprintf(stderr, "resuming: %zu finished rows in %s\n", resumed.size(), out.csv.c_str());
  auto is_resumed = [&](const StabilityCase& c, const StabilityMethod& m) {
    return resumed.find(row_key(c.name, m.method, budget_text(m.solve))) != nullptr;
  };

  // Progress in frame-cost units.
  const bool reference_listed =
      std::any_of(methods.begin(), methods.end(), [](const StabilityMethod& m) { return m.reference; });
  double total_cost = 0.0, resumed_cost = 0.0;
  for (const auto& c : cases) {
    const Scene s = c.apply(base);
    bool all_resumed = true;
    for (const auto& m : methods) {
      const double cost = s.frames * frame_cost(m, s);
      total_cost += cost;
      if (is_resumed(c, m))
        resumed_cost += cost;
      else
        all_resumed = false;
    }
    if (!reference_listed && !all_resumed) total_cost += s.frames * frame_cost(reference_method, s);
  }
  const double unit = std::max(1.0, total_cost / 1e6);  // at most ~1e6 units: fits an int
  std::optional<ProgressBar> bar;                       // rank 0's, over every rank's work
  double done_cost = resumed_cost;
  if (comm.is_root()) {
    bar.emplace("stability", static_cast<int>(total_cost / unit), static_cast<int>(resumed_cost / unit));
    std::string method_text;
    for (const auto& m : methods)
      method_text += (method_text.empty() ? "" : ", ") + m.method + " " + budget_text(m.solve);
    std::fprintf(stderr,
                 "fnopt stability: %zu case%s x %zu optimizers (%s), base %dx%d, %d frames at dt %s, %d thread%s%s, "
                 "output %s\n",
                 cases.size(), cases.size() == 1 ? "" : "s", methods.size(), method_text.c_str(), base.rows, base.cols,
                 base.frames, dt_text(base.dt).c_str(), threads, threads == 1 ? "" : "s",
                 comm.size() > 1 ? (", " + std::to_string(comm.size()) + " processes").c_str() : "", study.out.c_str());
  }

  // The tasks: one per case not resumed whole, its Newton reference and every row measured
  // against it (the reference lives in memory, so a case stays on one rank), spread over the
  // ranks largest first.
  const bool root = comm.is_root();
  std::vector<std::size_t> tasks;
  std::vector<double> task_costs;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Scene s = cases[k].apply(base);
    double cost = 0.0;
    bool all_resumed = true;
    for (const auto& m : methods)
      if (!is_resumed(cases[k], m)) cost += s.frames * frame_cost(m, s), all_resumed = false;
    if (all_resumed) continue;
    tasks.push_back(k);
    task_costs.push_back(cost + (reference_listed ? 0.0 : s.frames * frame_cost(reference_method, s)));
  }
  const std::vector<int> rank_of = schedule_largest_first(task_costs, comm.size());
  // Every rank planned from the same stability.csv: none may rewrite it before all have read it.
  comm.barrier();

  // Rank 0's view: the rows finished anywhere, by case and method; stability.csv holds them in
  // the order of a one-process run (rows this run does not redo, then case by case, method by
  // method). A row is kept as measured and as its CSV text: rows from other ranks arrive as text.
  struct FinishedRow {
    StabilityRow row;
    std::vector<std::string> cells;
  };
  std::map<std::pair<std::size_t, std::size_t>, FinishedRow> finished;
  std::set<std::string> planned;
  for (const StabilityCase& c : cases)
    for (const StabilityMethod& m : methods) planned.insert(row_key(c.name, m.method, budget_text(m.solve)));
  // Rows of the earlier CSV that this run does not redo (other cases, methods or budgets) stay
  // in it: resuming with a subset never drops finished work.
  const std::vector<std::vector<std::string>> unplanned = resumed.unplanned(planned);
  std::vector<StabilityRow> rows;
  CsvTable table(stability_columns());
  auto assemble = [&] {
    rows.clear();
    table = CsvTable(stability_columns());
    for (const auto& cells : unplanned) table.add_row(cells);
    for (std::size_t k = 0; k < cases.size(); ++k)
      for (std::size_t j = 0; j < methods.size(); ++j) {
        if (const auto* earlier =
                resumed.find(row_key(cases[k].name, methods[j].method, budget_text(methods[j].solve)))) {
          rows.push_back(stability_row_from_csv(*earlier));
          rows.back().reference = methods[j].reference;
          table.add_row(*earlier);
        } else if (const auto it = finished.find({k, j}); it != finished.end()) {
          rows.push_back(it->second.row);
          table.add_row(it->second.cells);
        }
      }
  };
  // Rank 0 records a finished row, rewrites the CSV and prints it.
  auto record = [&](std::size_t k, std::size_t j, const StabilityRow& row, const std::vector<std::string>& cells) {
    finished[{k, j}] = {row, cells};
    assemble();
    table.write(out.csv);
    bar->update(static_cast<int>(done_cost / unit), cases[k].name + " " + methods[j].method + " done");
    print_row(row);
    if (methods[j].reference && row.unconverged_steps > 0) {
      clear_bar_line();
      std::fprintf(stderr, "warning: newton on %s: %d step%s did not converge (%s)\n", cases[k].name.c_str(),
                   row.unconverged_steps, row.unconverged_steps == 1 ? "" : "s", row.unconverged_statuses.c_str());
    }
  };
  // A case from another rank: "case\n" then its rows, each "method index, cells" separated by
  // the unit separator, rows by the record separator.
  std::set<std::size_t> received;
  auto record_message = [&](const std::string& message) {
    const std::size_t end = message.find('\n');
    int k = 0;
    parse_int(std::string_view(message).substr(0, end), k);
    for (std::string_view line : split(std::string_view(message).substr(end + 1), '\x1e')) {
      if (line.empty()) continue;
      std::vector<std::string> cells;
      for (std::string_view cell : split(line, '\x1f')) cells.emplace_back(cell);
      int j = 0;
      parse_int(cells.front(), j);
      cells.erase(cells.begin());
      StabilityRow row = stability_row_from_csv(cells);
      row.reference = methods[j].reference;
      record(k, j, row, cells);
    }
    received.insert(k);
    done_cost += task_costs[std::find(tasks.begin(), tasks.end(), static_cast<std::size_t>(k)) - tasks.begin()];
    write_report(out, study, rows, table, started, false);
  };
  auto take_arrived = [&] {
    Communicator::Message message;
    while (comm.take_arrived(message)) record_message(message.text);
  };

  auto run_with_progress = [&](const Scene& scene, const StabilityMethod& m, const std::string& label) {
    const double weight = frame_cost(m, scene);
    StabilityRun run = run_stability_rollout(scene, m, factory, {}, [&](int done, int, const StepRecord& s) {
      if (!root) return;
      take_arrived();
      char status[160];
      std::snprintf(status, sizeof status, "%s: %.1f ms/step, strain %.0f%%", label.c_str(), s.wall_ms,
                    100 * s.max_strain);
      bar->update(static_cast<int>((done_cost + done * weight) / unit), status);
    });
    done_cost += scene.frames * weight;
    return run;
  };

  for (std::size_t t = 0; t < tasks.size(); ++t) {
    if (rank_of[t] != comm.rank()) continue;
    const std::size_t k = tasks[t];
    const StabilityCase& c = cases[k];
    const Scene scene = c.apply(base);
    StabilityRun reference = run_with_progress(scene, reference_method, "newton reference " + c.name);
    if (reference.failed || reference.rollout.diverged) {
      clear_bar_line();
      std::fprintf(stderr, "warning: the Newton reference of %s %s%s\n", c.name.c_str(),
                   reference.failed ? "failed: " : "",
                   reference.failed ? reference.error.c_str() : reference.rollout.divergence.c_str());
    }
    std::string message = std::to_string(k) + "\n";
    for (std::size_t j = 0; j < methods.size(); ++j) {
      const StabilityMethod& m = methods[j];
      if (is_resumed(c, m)) continue;
      const StabilityRow row =
          m.reference ? stability_row(c.name, m, reference, &reference)  // counted above
                      : stability_row(c.name, m, run_with_progress(scene, m, m.method + " " + c.name), &reference);
      const std::vector<std::string> cells = stability_csv_row(row);
      if (root) {
        record(k, j, row, cells);
        continue;
      }
      message += std::to_string(j);
      for (const std::string& cell : cells) message += '\x1f' + cell;
      message += '\x1e';
    }
    if (root)
      write_report(out, study, rows, table, started, false);
    else
      comm.send_to_root(message);
  }
  if (!root) return;
  for (std::size_t t = 0; t < tasks.size(); ++t)
    while (rank_of[t] != 0 && !received.count(tasks[t])) record_message(comm.wait_for().text);
  assemble();
  bar->finish();
  table.write(out.csv);
  write_report(out, study, rows, table, started, true);
  std::printf("%s", stability_console_table(rows).c_str());
  std::printf("\nwhat fails where:\n");
  for (const auto& line : stability_summary(rows, method_names)) std::printf("- %s\n", line.c_str());
  std::printf("wrote %s, %s and %s (%d thread%s)\n", out.csv.c_str(), out.svg.c_str(), out.report.c_str(), threads,
              threads == 1 ? "" : "s");
}

}  // namespace fnopt
