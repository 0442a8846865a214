#include <fnopt/viewer/rollout_view.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fnopt/contact/obstacle.hpp>
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

// v's coordinates, as floats, at the end of `values`.
void append(std::vector<float>& values, const Vec3& v) {
  values.insert(values.end(), {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())});
}

// A mesh's triangles, and its vertices without the motion's translation (the offsets carry it):
// at rest, or at every frame's time for an animated mesh.
void add_mesh(const Obstacle& o, const std::vector<double>& times, ObstacleView& shown) {
  const MeshShape& mesh = *o.mesh();
  for (const auto& triangle : mesh.triangles())
    shown.triangles.insert(shown.triangles.end(), triangle.begin(), triangle.end());
  shown.vertex_count = mesh.vertex_count();
  std::vector<Vec3> posed;
  for (const double t : mesh.animated() ? times : std::vector<double>{0.0}) {
    o.mesh_vertices(t, Vec3::Zero(), posed);
    for (const Vec3& p : posed) append(shown.vertices, p);
  }
}

// Obstacle `o` as the page draws it at the frames' `times`.
ObstacleView obstacle_view(const Obstacle& o, const std::vector<double>& times) {
  ObstacleView shown;
  shown.shape = shape_name(o.shape());
  const Vec3 axis = o.shape() == ObstacleShape::Plane ? o.axis().normalized() : o.axis();
  shown.point = {o.point().x(), o.point().y(), o.point().z()};
  shown.axis = {axis.x(), axis.y(), axis.z()};
  shown.radius = o.radius();
  for (const double t : times) append(shown.offsets, o.offset(t));
  if (o.is_mesh()) add_mesh(o, times, shown);
  return shown;
}

// One obstacle of the /meta JSON.
std::string obstacle_json(const ObstacleView& o) {
  std::string text = "{\"shape\":" + json_string(o.shape) + ",\"point\":" + json_array(o.point) +
                     ",\"axis\":" + json_array(o.axis) + ",\"radius\":" + json_number(o.radius) +
                     ",\"offsets\":" + json_array(o.offsets);
  if (o.vertex_count > 0)
    text += ",\"triangle_count\":" + std::to_string(o.triangles.size() / 3) +
            ",\"vertex_count\":" + std::to_string(o.vertex_count) +
            ",\"vertex_frames\":" + std::to_string(o.vertex_frames());
  return text + "}";
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

  if (file.has_attribute("fnopt_version") && file.has_attribute("scene"))
    for (const Obstacle& o : read_rollout_scene(path).obstacles) view.obstacles.push_back(obstacle_view(o, view.times));

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
  std::string obstacles = "[";
  for (const ObstacleView& o : view.obstacles) obstacles += (obstacles.size() > 1 ? "," : "") + obstacle_json(o);
  obstacles += "]";
  return "{\"name\":" + json_string(view.name) + ",\"kind\":" + json_string(view.kind) +
         ",\"optimizer\":" + json_string(view.optimizer) + ",\"divergence\":" + json_string(view.divergence) +
         ",\"rows\":" + std::to_string(view.rows) + ",\"cols\":" + std::to_string(view.cols) +
         ",\"frames\":" + std::to_string(view.frames()) + ",\"faces\":" + std::to_string(view.faces.size() / 3) +
         ",\"times\":" + json_array(view.times) + ",\"handle_count\":" + std::to_string(view.handle_count) +
         ",\"handle_positions\":" + json_array(view.handle_positions) + ",\"series\":" + series +
         ",\"max_strain\":" + json_number(largest_finite(view.strain)) +
         ",\"reference\":" + (view.reference_name.empty() ? "null" : json_string(view.reference_name)) +
         ",\"max_distance\":" + (view.distance.empty() ? "null" : json_number(largest_finite(view.distance))) +
         ",\"obstacles\":" + obstacles + "}";
}

}  // namespace fnopt
