#include <fnopt/studies/compare/compare_plot.hpp>

#include <algorithm>
#include <map>

#include <fnopt/studies/compare/compare_frontier.hpp>

namespace fnopt {

PlotFigure make_compare_plot(const std::vector<RunResult>& results, const std::vector<std::string>& methods,
                             const std::vector<std::string>& resolutions, const std::vector<std::string>& motions,
                             int threads, const std::vector<std::string>& notes) {
  PlotFigure figure;
  figure.title = "fnopt compare: error against run time (log-log; mean over " + std::to_string(motions.size()) +
                 " motion" + (motions.size() == 1 ? "" : "s") + ")";
  figure.notes = notes;
  figure.marked_meaning = "diverged in at least one motion (error: the mean over the motions it finished)";
  const bool have_arcsim =
      std::any_of(results.begin(), results.end(), [](const RunResult& r) { return std::isfinite(r.e_cd_arcsim); });
  struct Metric {
    std::string title, y_label;
    double RunResult::*value;
    double scale;
    bool newton_is_reference;
  };
  std::vector<Metric> metrics = {
      {"e_CD x 10^3 vs the Newton reference", "e_CD x 10^3 (Chamfer, vs Newton)", &RunResult::e_cd, 1e3, true},
      {"per-step error vs the Newton step", "mean (L(a_N) - L*)/(L(a_0) - L*)", &RunResult::step_mean, 1.0, true}};
  if (have_arcsim)
    metrics.push_back(
        {"e_CD x 10^3 vs ARCSim", "e_CD x 10^3 (Chamfer, vs ARCSim)", &RunResult::e_cd_arcsim, 1e3, false});
  const std::string x_label = threads == 1 ? "ms/frame, 1 thread (after warm-up; wall time x CPU share)"
                                           : "ms/frame, " + std::to_string(threads) + " threads (after warm-up)";
  figure.columns = static_cast<int>(metrics.size());  // one row of panels per resolution
  for (const std::string& res : resolutions) {
    for (const Metric& metric : metrics) {
      PlotPanel panel;
      panel.title = metric.title + ", " + resolution_title(res);
      panel.x_label = x_label;
      panel.y_label = metric.y_label;
      for (const std::string& method : methods) {
        std::map<int, std::vector<const RunResult*>> by_budget;
        for (const auto& r : results)
          if (r.resolution == res && r.spec.method == method) by_budget[r.spec.budget].push_back(&r);
        if (by_budget.empty()) continue;
        PlotSeries series;
        series.name = method;
        for (const auto& [budget, runs] : by_budget) {
          std::vector<double> ms, value;
          bool diverged = false;
          for (const auto* r : runs) {
            ms.push_back(plotted_ms(*r, threads));
            value.push_back(metric.scale * (r->*metric.value));
            diverged = diverged || r->diverged || r->failed;
          }
          if (is_reference_run({method, budget}) && metric.newton_is_reference) {
            panel.vertical_lines.push_back({mean_finite(ms), method + " (the reference)"});
            continue;
          }
          series.points.push_back({mean_finite(ms), mean_finite(value),
                                   is_converged_run({method, budget}) ? "" : "N=" + std::to_string(budget), diverged});
        }
        if (series.points.empty()) continue;
        panel.series.push_back(series);
      }
      if (&metric == &metrics.front()) {  // the error-time frontier of the means over the motions
        std::vector<MeanRun> means = finished_means(results, res, threads);
        means.erase(
            std::remove_if(means.begin(), means.end(), [](const MeanRun& m) { return is_reference_run(m.spec); }),
            means.end());
        std::vector<std::pair<double, double>> points;
        for (const MeanRun& m : means) points.push_back({m.ms, m.e_cd});
        const std::vector<bool> optimal = pareto_optimal(points);
        PlotSeries front;
        front.name = "frontier (fastest for its error)";
        front.band = true;
        for (std::size_t k = 0; k < means.size(); ++k)
          if (optimal[k]) front.points.push_back({means[k].ms, 1e3 * means[k].e_cd, "", false});
        std::sort(front.points.begin(), front.points.end(),
                  [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
        if (front.points.size() > 1) panel.series.push_back(front);
      }
      figure.panels.push_back(panel);
    }
  }
  return figure;
}

}  // namespace fnopt
