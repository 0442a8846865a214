#include <fnopt/viewer/web_assets.hpp>

#include <filesystem>

#include <fnopt/util/error.hpp>
#include <fnopt/util/installed_data.hpp>

namespace fnopt {

namespace fs = std::filesystem;

namespace {

// Our page, every file by name: nothing else under the directory is served.
const char* const kPageFiles[] = {"index.html",       "viewer.css",      "viewer.js",    "rollout_player.js",
                                  "compare_chart.js", "series_plots.js", "colour_map.js"};

// Debian's libjs-three. The URLs keep the package's layout, so that OrbitControls' own import
// ("../../../build/three.module.js") resolves to the same module as ours.
const char* const kThreeDirectory = "/usr/share/javascript/three";
const char* const kThreeFiles[] = {"build/three.module.js", "examples/jsm/controls/OrbitControls.js"};

fs::path page_directory() {
  return fs::path(installed_data_path("web/index.html", "src/fnopt/viewer/web/index.html")).parent_path();
}

std::string content_type_of(const fs::path& file) {
  const std::string extension = file.extension().string();
  if (extension == ".html") return "text/html; charset=utf-8";
  if (extension == ".css") return "text/css; charset=utf-8";
  return "text/javascript; charset=utf-8";
}

}  // namespace

std::vector<WebAsset> find_web_assets() {
  std::vector<WebAsset> assets;
  const fs::path page = page_directory();
  for (const char* name : kPageFiles) {
    const fs::path file = page / name;
    require(fs::is_regular_file(file), file.string(), "missing: the viewer's page is not installed with fnopt");
    assets.push_back({std::string("/") + name, file.string(), content_type_of(file)});
  }
  for (const char* name : kThreeFiles) {
    // Debian links build/three.module.js to ../three.module.js: serve what the link points to.
    const fs::path file = fs::path(kThreeDirectory) / name;
    require(fs::is_regular_file(file), file.string(), "missing: install three.js (apt-get install libjs-three)");
    assets.push_back({std::string("/three/") + name, fs::canonical(file).string(), content_type_of(file)});
  }
  return assets;
}

}  // namespace fnopt
