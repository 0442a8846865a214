#include <fnopt/studies/compare/compare_frontier.hpp>

#include <algorithm>
#include <map>

namespace fnopt {

std::vector<bool> pareto_optimal(const std::vector<std::pair<double, double>>& points) {
  std::vector<bool> optimal(points.size(), false);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [ms, error] = points[i];
    if (!std::isfinite(ms) || !std::isfinite(error)) continue;
    optimal[i] = std::none_of(points.begin(), points.end(), [&](const std::pair<double, double>& other) {
      return std::isfinite(other.first) && std::isfinite(other.second) && other.first <= ms && other.second <= error &&
             (other.first < ms || other.second < error);
    });
  }
  return optimal;
}

void mark_frontier(std::vector<RunResult>& results, int threads) {
  std::map<std::pair<std::string, std::string>, std::vector<std::size_t>> scenes;
  for (std::size_t i = 0; i < results.size(); ++i) scenes[{results[i].resolution, results[i].motion}].push_back(i);
  for (const auto& [scene, indices] : scenes) {
    std::vector<std::pair<double, double>> points;
    for (std::size_t i : indices) {
      const RunResult& r = results[i];
      const bool finished = !r.diverged && !r.failed;
      points.push_back({finished ? plotted_ms(r, threads) : NAN, finished ? r.e_cd : NAN});
    }
    const std::vector<bool> optimal = pareto_optimal(points);
    for (std::size_t k = 0; k < indices.size(); ++k) results[indices[k]].frontier = optimal[k];
  }
}

std::vector<MeanRun> finished_means(const std::vector<RunResult>& results, const std::string& resolution, int threads) {
  std::map<std::pair<std::string, int>, std::vector<const RunResult*>> runs;
  std::vector<std::pair<std::string, int>> order;
  for (const auto& r : results)
    if (r.resolution == resolution) {
      auto& list = runs[{r.spec.method, r.spec.budget}];
      if (list.empty()) order.push_back({r.spec.method, r.spec.budget});
      list.push_back(&r);
    }
  std::vector<MeanRun> means;
  for (const auto& key : order) {
    const auto& list = runs[key];
    if (std::any_of(list.begin(), list.end(), [](const RunResult* r) { return r->diverged || r->failed; })) continue;
    std::vector<double> ms, cd;
    for (const auto* r : list) ms.push_back(plotted_ms(*r, threads)), cd.push_back(r->e_cd);
    means.push_back({{key.first, key.second}, mean_finite(ms), mean_finite(cd)});
  }
  return means;
}

std::vector<LevelWinner> fastest_within(const std::vector<RunResult>& results, const std::string& resolution,
                                        const std::vector<double>& levels, int threads) {
  const std::vector<MeanRun> means = finished_means(results, resolution, threads);
  std::vector<LevelWinner> winners;
  for (double level : levels) {
    LevelWinner w;
    w.level = level;
    for (const MeanRun& m : means)
      if (!is_reference_run(m.spec) && m.e_cd <= level && !(m.ms >= w.ms))
        w.method = m.spec.method, w.budget = m.spec.budget, w.ms = m.ms, w.e_cd = m.e_cd;
    winners.push_back(w);
  }
  return winners;
}

}  // namespace fnopt
