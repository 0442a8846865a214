#include <fnopt/viewer/compare_directory.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/viewer/json_text.hpp>

namespace fnopt {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kNeededColumns = {"method",       "N",         "resolution", "motion",
                                                 "ms_per_frame", "e_cd_x1e3", "frontier"};

std::string scene_text_of(const fs::path& rollout) {
  const Hdf5File file(rollout.string(), Hdf5File::Mode::Read);
  return file.has_attribute("scene") ? file.string_attribute("scene") : std::string();
}

// compare names a reference by its scene's label and a 16-digit hash of the scene and solver
// (simulation/newton_reference.hpp); the label alone is ambiguous ("xy_v2" is a prefix of
// "xy_v2_opp"), so the hash's shape is checked and the scene stored in both files decides.
std::string reference_of(const fs::path& directory, const std::string& label, const fs::path& rollout) {
  const std::string prefix = "newton_reference_" + label + "_";
  const std::string scene = scene_text_of(rollout);
  for (const auto& entry : fs::directory_iterator(directory)) {
    const std::string name = entry.path().filename().string();
    if (name.size() != prefix.size() + 16 + 3 || name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - 3, 3, ".h5") != 0)
      continue;
    const std::string hash = name.substr(prefix.size(), 16);
    if (!std::all_of(hash.begin(), hash.end(), [](unsigned char c) { return std::isxdigit(c); })) continue;
    if (!scene.empty() && scene_text_of(entry.path()) == scene) return entry.path().string();
  }
  return "";
}

}  // namespace

CompareDirectory read_compare_directory(const std::string& path) {
  const fs::path directory(path);
  const fs::path csv = directory / "compare.csv";
  require(fs::is_directory(directory), path, "not a directory");
  require(fs::is_regular_file(csv), path, "no compare.csv: not a `fnopt compare` output directory");
  const CsvTable table = CsvTable::read(csv.string());
  CompareDirectory result;
  result.path = path;
  result.columns = table.columns();
  auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(result.columns.begin(), result.columns.end(), name) -
                                    result.columns.begin());
  };
  for (const auto& name : kNeededColumns)
    require(column(name) < result.columns.size(), csv.string(), "no '" + name + "' column");
  for (const auto& row : table.rows()) {
    CompareRun run;
    run.cells = row;
    // The name compare --keep-rollouts gives a run's rollout (studies/compare/compare_study.cpp): the
    // budget is left out for the converged reference run ("converged").
    const std::string method = row[column("method")], budget = row[column("N")];
    const std::string label = row[column("resolution")] + "_" + row[column("motion")];
    const bool numeric_budget =
        !budget.empty() && std::all_of(budget.begin(), budget.end(), [](unsigned char c) { return std::isdigit(c); });
    const fs::path rollout =
        directory / ("rollout_" + method + (numeric_budget ? "_" + budget : "") + "_" + label + ".h5");
    if (fs::is_regular_file(rollout)) {
      run.rollout = rollout.string();
      run.reference = reference_of(directory, label, rollout);
    }
    result.runs.push_back(std::move(run));
  }
  return result;
}

std::string compare_directory_json(const CompareDirectory& directory) {
  auto name_or_null = [](const std::string& file) {
    return file.empty() ? std::string("null") : json_string(fs::path(file).filename().string());
  };
  std::string columns = "[";
  for (std::size_t k = 0; k < directory.columns.size(); ++k)
    columns += (k ? "," : "") + json_string(directory.columns[k]);
  std::string rows = "[";
  for (std::size_t r = 0; r < directory.runs.size(); ++r) {
    const CompareRun& run = directory.runs[r];
    std::string cells = "[";
    for (std::size_t k = 0; k < run.cells.size(); ++k) cells += (k ? "," : "") + json_string(run.cells[k]);
    rows += (r ? "," : "") + std::string("{\"cells\":") + cells + "],\"rollout\":" + name_or_null(run.rollout) +
            ",\"reference\":" + name_or_null(run.reference) + "}";
  }
  return "{\"directory\":" + json_string(directory.path) + ",\"columns\":" + columns + "],\"rows\":" + rows + "]}";
}

}  // namespace fnopt
