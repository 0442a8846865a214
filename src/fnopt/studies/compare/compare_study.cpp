#include <fnopt/studies/compare/compare_study.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fnopt/studies/compare/compare_sweep.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

std::vector<Scene> compare_scenes(const Scene& base, const std::vector<GridSize>& resolutions,
                                  const std::vector<std::string>& motions) {
  std::vector<Scene> scenes;
  for (const GridSize& res : resolutions)
    for (const auto& motion : motions) {
      Scene scene = base;
      if (res.rows == res.cols) {
        apply_scene_setting(scene, "res", std::to_string(res.rows));
      } else {
        apply_scene_setting(scene, "rows", std::to_string(res.rows));
        apply_scene_setting(scene, "cols", std::to_string(res.cols));
      }
      if (base.trajectory.empty()) apply_scene_setting(scene, "motion", motion);
      scenes.push_back(scene);
      if (!base.trajectory.empty()) break;
    }
  return scenes;
}

std::string resolution_text(const Scene& scene) {
  return scene.rows == scene.cols ? std::to_string(scene.rows)
                                  : std::to_string(scene.rows) + "x" + std::to_string(scene.cols);
}

std::string motion_text(const Scene& scene) {
  return scene.trajectory.empty() ? scene.motion : std::filesystem::path(scene.trajectory).filename().string();
}

namespace {

void require_positive(const std::vector<double>& values, const std::string& field) {
  require(!values.empty(), field, "give at least one value");
  for (double value : values) require(std::isfinite(value) && value > 0.0, field, "must be positive numbers");
}

void require_budgets(const std::vector<int>& budgets, const std::string& field) {
  for (int budget : budgets) require(budget >= 1, field, "must be positive iteration budgets");
}

}  // namespace

void CompareStudy::validate() const {
  require(!scenes.empty(), "compare.scenes", "give at least one scene");
  require(!methods.empty(), "compare.methods", "give at least one optimizer");
  require(!out.empty(), "compare.out", "an output directory is required");
  require(reference == "newton" || reference == "newton-min", "compare.reference",
          "'" + reference + "': choose newton or newton-min");
  for (const auto& method : methods) {  // a bad name fails before any work
    OptimizerChoice choice = settings;
    choice.name = method;
    choice.make();
    if (!method_traits(method).learning_rate) continue;
    require(learning_rates.count(method) > 0, "compare.learning_rates",
            "'" + method + "' takes a learning rate: give its candidates");
    require_positive(learning_rates.at(method), "compare.learning_rates");
  }
  require_budgets(budgets, "compare.budgets");
  for (const auto& [method, given] : budgets_for) {
    require(std::find(methods.begin(), methods.end(), method) != methods.end(), "compare.budgets_for",
            "'" + method + "' is not among the optimizers");
    require_budgets(given, "compare.budgets_for");
  }
  for (const Scene& scene : scenes) {
    scene.validate();
    for (const auto& method : methods) {
      OptimizerChoice choice = settings;
      choice.name = method;
      choice.check_grid(scene.rows, scene.cols);
    }
  }
  require_positive(error_levels, "compare.error_levels");
  chamfer.validate();
  require(cd_stride >= 1, "compare.cd_stride",
          "must be at least 1 (every matched frame), got " + std::to_string(cd_stride));
  require(step_samples >= 1, "compare.step_samples", "must be positive");
}

std::vector<RunSpec> CompareStudy::runs() const { return compare_runs(methods, budgets, budgets_for); }

void run_compare_study(const CompareStudy& study, const Communicator& comm) { CompareSweep(study, comm).run_study(); }

std::vector<RunSpec> compare_runs(const std::vector<std::string>& methods, const std::vector<int>& budgets,
                                  const std::map<std::string, std::vector<int>>& capped) {
  std::vector<RunSpec> runs;
  for (const auto& method : methods) {
    const auto given = capped.find(method);
    switch (method_traits(method).budget) {
      case BudgetKind::ToTolerance:
        runs.push_back({method, 0});
        if (given != capped.end())
          for (int budget : given->second) runs.push_back({method, budget});
        break;
      case BudgetKind::OneSolve:
        runs.push_back({method, 1});
        break;
      case BudgetKind::Iterations:
        for (int budget : given != capped.end() ? given->second : budgets) runs.push_back({method, budget});
        break;
    }
  }
  return runs;
}

}  // namespace fnopt
