#include <fnopt/studies/compare/superres_report.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fnopt/methods/registry.hpp>
#include <fnopt/studies/compare/compare_aggregate.hpp>

namespace fnopt {

namespace fs = std::filesystem;

namespace {

// The super-resolution comparison: each learned method (fnopt, fnopt-ss, fnopt, ...) at
// each budget against every interpolation method, at the same (coarse) budget where it ran that
// one, else at its first budget (newton-interp32 runs to its tolerance, N = 1000 at most).
struct SuperresColumns {
  std::vector<std::string> methods;  // the learned method first, then the interpolation methods
  std::vector<int> budgets;          // one per method
  int budget = 0;                    // the learned method's
};

std::vector<SuperresColumns> superres_columns(const std::vector<RunResult>& results,
                                              const std::vector<std::string>& methods) {
  std::vector<SuperresColumns> columns;
  for (const auto& learned : methods) {
    if (!method_traits(learned).learned) continue;
    for (int budget : budgets_of(results, learned)) {
      SuperresColumns c;
      c.budget = budget;
      c.methods.push_back(learned);
      c.budgets.push_back(budget);
      for (const auto& method : methods)
        if (is_interpolated_method(method)) {
          const auto b = budgets_of(results, method);
          if (b.empty()) continue;
          c.methods.push_back(method);
          c.budgets.push_back(std::find(b.begin(), b.end(), budget) != b.end() ? budget : b.front());
        }
      if (c.methods.size() > 1) columns.push_back(c);
    }
  }
  return columns;
}

PlotFigure superres_figure(const std::vector<RunResult>& results, const std::vector<std::string>& resolutions,
                           const std::vector<SuperresColumns>& columns, const CompareReport& report) {
  PlotFigure figure;
  figure.title =
      "fnopt compare: zero-shot super-resolution (the learned methods' model on each grid vs solve coarse + "
      "interpolate)";
  figure.notes = report.notes;
  figure.notes.push_back("x: vertices of the fine grid (log); labels: the resolution (RxC = rows x columns)");
  figure.marked_meaning = "diverged (no error: it did not finish)";
  figure.columns = 2;
  struct Metric {
    std::string title, y_label;
    double Aggregate::*value;
    double scale;
  };
  const std::vector<Metric> metrics = {
      {"e_CD x 10^3 vs the Newton reference", "e_CD x 10^3", &Aggregate::e_cd, 1e3},
      {"e_3D x 10^2 vs the Newton reference", "e_3D x 10^2", &Aggregate::e_3d, 1e2},
      {"per-step error vs the Newton step", "mean (L(a_N) - L*)/(L(a_0) - L*)", &Aggregate::step, 1.0},
      {"run time", report.threads == 1 ? "ms/frame, 1 thread (wall x CPU share)" : "ms/frame", &Aggregate::ms, 1.0}};
  std::vector<std::string> order = resolutions;
  std::stable_sort(order.begin(), order.end(),
                   [](const std::string& a, const std::string& b) { return vertex_count_of(a) < vertex_count_of(b); });
  for (const Metric& metric : metrics) {
    PlotPanel panel;
    panel.title = metric.title;
    panel.x_label = "vertices";
    panel.y_label = metric.y_label;
    for (const auto& c : columns)
      for (std::size_t m = 0; m < c.methods.size(); ++m) {
        const std::string& method = c.methods[m];
        PlotSeries series;
        series.name = method_label(method, c.budgets[m]);
        for (const auto& res : order) {
          const Aggregate a = aggregate(results, res, method, c.budgets[m], report.threads);
          if (a.runs == 0) continue;
          series.points.push_back({static_cast<double>(vertex_count_of(res)), metric.scale * (a.*metric.value), res,
                                   a.diverged + a.failed > 0});
        }
        if (!series.points.empty()) panel.series.push_back(series);
      }
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace

void write_superres_section(MarkdownReport& md, const CompareReport& report, const std::vector<RunResult>& results) {
  const auto columns = superres_columns(results, report.methods);
  const std::string superres_svg = (fs::path(report.directory) / "superres.svg").string();
  if (!columns.empty()) {
    md.heading("Zero-shot super-resolution");
    md.paragraph(
        "The learned optimizer's models are trained on coarse grids: `fnopt-ss-32`, `fnopt` and the other "
        "learned methods run the one trained at 32x32 only, `fnopt-ss` the one trained on 32x32 to 100x100 grids "
        "(unless --model sets one for all). Super-evaluation runs each model unchanged on each grid. "
        "The ablation (`METHOD-interpK`) instead restricts the state (x_t, v_t) bilinearly to the grid with K "
        "vertices along the longer edge, solves the step there with METHOD (same budget N), and prolongs the "
        "acceleration bilinearly; handles keep their prescribed motion. Both are measured against the Newton "
        "reference on the fine grid. Lower is better; the better error of each row is in bold.");
    for (const auto& c : columns) {
      std::vector<std::string> head = {"resolution", "vertices"};
      const char* metric_names[] = {"e_CD x10^3", "e_3D x10^2", "per-step error", "ms/frame"};
      double Aggregate::*fields[] = {&Aggregate::e_cd, &Aggregate::e_3d, &Aggregate::step, &Aggregate::ms};
      const double scales[] = {1e3, 1e2, 1.0, 1.0};
      for (const char* metric : metric_names)
        for (std::size_t m = 0; m < c.methods.size(); ++m)
          head.push_back(std::string(metric) + ": " + method_label(c.methods[m], c.budgets[m]));
      std::vector<std::vector<std::string>> rows;
      std::vector<std::string> order = report.resolutions;
      std::stable_sort(order.begin(), order.end(), [](const std::string& a, const std::string& b) {
        return vertex_count_of(a) < vertex_count_of(b);
      });
      int learned_wins = 0, compared = 0;
      for (const auto& res : order) {
        std::vector<Aggregate> a;
        for (std::size_t m = 0; m < c.methods.size(); ++m)
          a.push_back(aggregate(results, res, c.methods[m], c.budgets[m], report.threads));
        if (std::all_of(a.begin(), a.end(), [](const Aggregate& x) { return x.runs == 0; })) continue;
        std::vector<std::string> row = {res, std::to_string(vertex_count_of(res))};
        for (int m = 0; m < 4; ++m) {
          double best = INFINITY;
          for (const auto& x : a)
            if (std::isfinite(x.*fields[m])) best = std::min(best, x.*fields[m]);
          for (const auto& x : a) {
            std::string cell = x.runs ? report_number(scales[m] * (x.*fields[m])) : "";
            if (x.diverged + x.failed) cell += " (diverged)";
            if (m < 3 && x.runs && x.*fields[m] == best && a.size() > 1) cell = "**" + cell + "**";
            row.push_back(cell);
          }
        }
        if (a[0].runs && a.size() > 1 && std::isfinite(a[0].e_cd)) {
          bool wins = true;
          for (std::size_t k = 1; k < a.size(); ++k)  // against interpolation at the same budget
            if (c.budgets[k] == c.budget && a[k].runs && std::isfinite(a[k].e_cd) && a[k].e_cd < a[0].e_cd)
              wins = false;
          ++compared;
          learned_wins += wins;
        }
        rows.push_back(row);
      }
      md.heading(c.methods.front() + " at N = " + std::to_string(c.budget), 3);
      md.table(head, rows);
      if (compared)
        md.paragraph("Super-evaluation (" + method_label(c.methods.front(), c.budget) +
                     ") has a lower e_CD than each interpolation method run at the same N at " +
                     std::to_string(learned_wins) + " of " + std::to_string(compared) + " resolutions.");
    }
    write_svg(superres_svg, superres_figure(results, report.resolutions, columns, report));
    md.image("superres.svg", "error and ms/frame against the vertex count: super-evaluation vs interpolation");
  }
}

}  // namespace fnopt
