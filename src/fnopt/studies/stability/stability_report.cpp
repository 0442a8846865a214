#include <fnopt/studies/stability/stability_report.hpp>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/io/markdown_report.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/version.hpp>

namespace fnopt {

void write_stability_report(const StabilityStudy& study, const StabilityReportFiles& files,
                            const std::vector<StabilityRow>& rows, const CsvTable& table, bool complete) {
  const Scene& base = study.base;
  const auto& cases = study.cases;
  const auto& methods = study.methods;
  const auto& method_names = study.method_names;
  const int threads = study.threads;
  std::vector<std::string> notes = {std::to_string(base.frames) + " frames at dt = " + dt_text(base.dt) +
                                    " s on the base scene; " + std::to_string(threads) + " thread" +
                                    (threads == 1 ? "" : "s") +
                                    "; marked: diverged (strain > 300 % or non-finite) or error"};
  write_svg(files.svg, stability_plot(rows, cases, method_names, notes));

  MarkdownReport report("fnopt stability");
  report.paragraph(std::string(complete ? "" : "**Partial: the study is still running or was stopped.** ") +
                   "Stiff and extreme cases, every inner optimizer on each, against the case's Newton reference "
                   "(run to a residual acceleration of " +
                   NewtonOptimizer::reference_stop_text() +
                   " each step; steps that stop short are counted below). "
                   "fnopt " FNOPT_VERSION ", started " +
                   files.started + ", " + std::to_string(threads) + " thread" + (threads == 1 ? "" : "s") + ".");
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
  report.write(files.report);
}

}  // namespace fnopt
