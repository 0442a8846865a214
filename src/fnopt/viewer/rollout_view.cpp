#include <fnopt/viewer/rollout_view.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/viewer/json_text.hpp>
#include <fnopt/viewer/vertex_scalars.hpp>

namespace fnopt {

namespace {

// Only the series the page plots, in the order it plots them.
const char* const kPlottedSeries[] = {"step_max_strain", "step_energy", "step_iterations", "step_wall_ms"};

void require_readable_file(const std::string& path) {
  namespace fs = std::filesystem;
  require(fs::exists(path), path, "no such file");
  require(fs::is_regular_file(path), path, "not a file (a compare directory is viewed without --against)");
}

std::vector<float> flattened(const TrajectoryFrames& frames) {
  std::vector<float> all;
  all.reserve(frames.positions.size() * 3 * frames.rows * frames.cols);
  for (const auto& frame : frames.positions) all.insert(all.end(), frame.data(), frame.data() + frame.size());
  return all;
}

float largest_finite(const std::vector<float>& values) {
  float largest = 0.0f;
  for (const float v : values)
    if (std::isfinite(v)) largest = std::max(largest, v);
  return largest;
}

}  // namespace

RolloutView load_rollout_view(const std::string& path, const std::string& reference_path) {
  require_readable_file(path);
  const TrajectoryFrames frames = read_trajectory_frames(path);
  require(frames.rows >= 2 && frames.cols >= 2, path, "'positions' must have at least 2 rows and 2 columns");
  const Hdf5File file(path, Hdf5File::Mode::Read);
  RolloutView view;
  view.name = std::filesystem::path(path).filename().string();
  view.kind = file.has_attribute("fnopt_version") ? "fnopt rollout" : "ARCSim-layout file";
  if (file.has_attribute("optimizer")) view.optimizer = file.string_attribute("optimizer");
  if (file.has_attribute("divergence")) view.divergence = file.string_attribute("divergence");
  view.rows = frames.rows;
  view.cols = frames.cols;
  view.times = frames.times;
  view.positions = flattened(frames);
  const int T = view.frames(), N = view.vertices();

  if (file.has("faces")) {
    view.faces = file.read_ints("faces");
    require(view.faces.size() % 3 == 0, path, "'faces' must have shape [F, 3]");
    require(std::all_of(view.faces.begin(), view.faces.end(), [&](int v) { return v >= 0 && v < N; }), path,
            "'faces' refers to a vertex outside the grid");
  } else {  // the grid's own split of each quad (cloth/grid.hpp)
    for (int i = 0; i + 1 < view.rows; ++i)
      for (int j = 0; j + 1 < view.cols; ++j) {
        const int a = i * view.cols + j, b = a + 1, d = a + view.cols, e = d + 1;
        view.faces.insert(view.faces.end(), {a, b, e, a, e, d});
      }
  }
  if (file.has("handle_positions")) {
    const auto dims = file.dims("handle_positions");
    require(dims.size() == 3 && dims[0] == static_cast<hsize_t>(T) && dims[2] == 3, path,
            "'handle_positions' must have shape [T, H, 3] with T the frame count");
    view.handle_count = static_cast<int>(dims[1]);
    view.handle_positions = file.read_floats("handle_positions");
  }
  for (const char* name : kPlottedSeries) {
    if (!file.has(name)) continue;
    std::vector<double> values = file.read_doubles(name);
    require(static_cast<int>(values.size()) == T - 1, path,
            std::string("'") + name + "' must have one value per step (frames - 1)");
    view.series.emplace_back(name, std::move(values));
  }

  // Rest lengths from rest_positions where the file has them (both layouts do), else frame 0.
  std::vector<float> rest;
  if (file.has("rest_positions")) rest = file.read_floats("rest_positions");
  if (rest.size() != static_cast<std::size_t>(3 * N))
    rest.assign(view.positions.begin(), view.positions.begin() + 3 * N);
  view.strain = vertex_strain(frames, rest);

  if (!reference_path.empty()) {
    require_readable_file(reference_path);
    const TrajectoryFrames reference = read_trajectory_frames(reference_path);
    require(reference.rows >= 2 && reference.cols >= 2, reference_path,
            "'positions' must have at least 2 rows and 2 columns");
    view.reference_name = std::filesystem::path(reference_path).filename().string();
    view.distance = vertex_distance(frames, reference);
  }
  return view;
}

std::string rollout_metadata_json(const RolloutView& view) {
  std::string series = "{";
  for (const auto& [name, values] : view.series)
    series += (series.size() > 1 ? "," : "") + json_string(name) + ":" + json_array(values);
  series += "}";
  return "{\"name\":" + json_string(view.name) + ",\"kind\":" + json_string(view.kind) +
         ",\"optimizer\":" + json_string(view.optimizer) + ",\"divergence\":" + json_string(view.divergence) +
         ",\"rows\":" + std::to_string(view.rows) + ",\"cols\":" + std::to_string(view.cols) +
         ",\"frames\":" + std::to_string(view.frames()) + ",\"faces\":" + std::to_string(view.faces.size() / 3) +
         ",\"times\":" + json_array(view.times) + ",\"handle_count\":" + std::to_string(view.handle_count) +
         ",\"handle_positions\":" + json_array(view.handle_positions) + ",\"series\":" + series +
         ",\"max_strain\":" + json_number(largest_finite(view.strain)) +
         ",\"reference\":" + (view.reference_name.empty() ? "null" : json_string(view.reference_name)) +
         ",\"max_distance\":" + (view.distance.empty() ? "null" : json_number(largest_finite(view.distance))) + "}";
}

}  // namespace fnopt
