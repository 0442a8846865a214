#include <fnopt/simulation/rollout_file.hpp>

#include <regex>
#include <utility>
#include <vector>

#include <fnopt/contact/mesh_source.hpp>
#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/version.hpp>

namespace fnopt {

namespace {

// One entry per step that produced a kept frame (S = T - 1). A step that diverged kept no frame:
// it is described by the attributes diverged_step and divergence, not by NaNs here.
void write_steps(Hdf5File& file, const RolloutResult& rollout) {
  const hsize_t S = rollout.positions.size() - 1;
  auto column = [&](auto member) {
    std::vector<double> values;
    for (hsize_t k = 0; k < S; ++k) values.push_back(rollout.steps[k].*member);
    return values;
  };
  file.write("step_wall_ms", {S}, column(&StepRecord::wall_ms).data());
  file.write("step_loss", {S}, column(&StepRecord::loss).data());
  file.write("step_initial_loss", {S}, column(&StepRecord::initial_loss).data());
  file.write("step_gradient_norm", {S}, column(&StepRecord::gradient_norm).data());
  file.write("step_initial_gradient_norm", {S}, column(&StepRecord::initial_gradient_norm).data());
  file.write("step_max_strain", {S}, column(&StepRecord::max_strain).data());
  file.write("step_energy", {S}, column(&StepRecord::energy).data());
  std::vector<int> iterations, status;
  for (hsize_t k = 0; k < S; ++k) {
    iterations.push_back(rollout.steps[k].iterations);
    status.push_back(static_cast<int>(rollout.steps[k].status));
  }
  file.write("step_iterations", {S}, iterations.data());
  file.write("step_status", {S}, status.data());
  std::string legend;
  for (int k = 0; k <= static_cast<int>(SolveStatus::PrecisionLimit); ++k)
    legend += (k ? ", " : "") + std::to_string(k) + " " + to_string(static_cast<SolveStatus>(k));
  file.set_attribute("legend", legend, "step_status");
}

std::string mesh_dataset(std::size_t obstacle, const char* what) {
  return "mesh_" + std::to_string(obstacle) + "_" + what;
}

// Each mesh obstacle's frames as given and its triangles, named by its place among the obstacles
// (1-based), its source on the vertices.
void write_meshes(Hdf5File& file, const std::vector<Obstacle>& obstacles) {
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    if (!obstacles[k].is_mesh()) continue;
    const std::vector<TriangleMesh>& frames = obstacles[k].mesh()->frames_as_given();
    const hsize_t F = frames.size(), V = frames.front().vertices.size(), T = frames.front().triangles.size();
    std::vector<double> vertices;
    vertices.reserve(F * V * 3);
    for (const TriangleMesh& frame : frames)
      for (const Vec3& v : frame.vertices) vertices.insert(vertices.end(), v.data(), v.data() + 3);
    file.write(mesh_dataset(k + 1, "vertices"), {F, V, 3}, vertices.data());
    file.write(mesh_dataset(k + 1, "triangles"), {T, 3}, frames.front().triangles.front().data());
    file.set_attribute("source", obstacles[k].mesh_source(), mesh_dataset(k + 1, "vertices"));
  }
}

void write_file(const std::string& path, const RolloutResult& rollout, const std::string& scene_text,
                const std::string& optimizer_settings, const std::vector<Obstacle>& obstacles) {
  write_atomically(path, [&](const std::string& temporary) {
    Hdf5File file(temporary, Hdf5File::Mode::Create);
    const Grid& g = rollout.grid;
    const hsize_t T = rollout.positions.size(), R = g.rows, C = g.cols, H = rollout.handle_vertices.size();

    std::vector<float> positions(T * R * C * 3);
    for (hsize_t t = 0; t < T; ++t)
      std::copy(rollout.positions[t].data(), rollout.positions[t].data() + R * C * 3, &positions[t * R * C * 3]);
    file.write("positions", {T, R, C, 3}, positions.data());

    std::vector<float> handles;
    for (const auto& frame : rollout.handle_targets)
      for (const Vec3& p : frame)
        for (int c = 0; c < 3; ++c) handles.push_back(static_cast<float>(p[c]));
    file.write("handle_positions", {T, H, 3}, handles.data());
    file.write("handle_vertices", {H}, rollout.handle_vertices.data());

    const Eigen::VectorXf rest =
        (rollout.rest_positions.size() == g.dof_count() ? rollout.rest_positions : g.rest_positions()).cast<float>();
    file.write("rest_positions", {R, C, 3}, rest.data());
    const auto faces = g.triangles();
    file.write("faces", {static_cast<hsize_t>(faces.rows()), 3}, faces.data());
    file.write("times_s", {T}, rollout.times.data());

    write_steps(file, rollout);
    write_meshes(file, obstacles);
    for (const auto& [dataset, unit] : std::vector<std::pair<const char*, const char*>>{
             {"positions", "m"},
             {"handle_positions", "m"},
             {"rest_positions", "m"},
             {"times_s", "s"},
             {"step_wall_ms", "ms"},
             {"step_loss", "J (L(a) of the step's objective, relative to x^)"},
             {"step_initial_loss", "J"},
             {"step_gradient_norm", "J s^2/m (|dL/da| over the free dofs)"},
             {"step_initial_gradient_norm", "J s^2/m"},
             {"step_max_strain", "fraction (|e|/h - 1 of the longest edge)"},
             {"step_energy", "J (kinetic + potential after the step)"}})
      file.set_attribute("unit", std::string(unit), dataset);

    file.set_attribute("rows", g.rows);
    file.set_attribute("cols", g.cols);
    file.set_attribute("dt", rollout.dt);
    file.set_attribute("dt_unit", std::string("s"));
    file.set_attribute("scene", scene_text);
    file.set_attribute("optimizer", optimizer_settings);
    file.set_attribute("fnopt_version", std::string(FNOPT_VERSION));
    file.set_attribute("diverged", rollout.diverged ? 1 : 0);
    file.set_attribute("diverged_step", rollout.diverged ? static_cast<int>(rollout.steps.size()) : 0);
    file.set_attribute("divergence", rollout.divergence);
  });
}

}  // namespace

void write_rollout_file(const std::string& path, const RolloutResult& rollout, const Scene& scene,
                        const std::string& optimizer_settings) {
  write_file(path, rollout, to_scene_text(scene), optimizer_settings, scene.obstacles);
}

void write_rollout_file(const std::string& path, const RolloutResult& rollout, const std::string& scene_text,
                        const std::string& optimizer_settings) {
  write_file(path, rollout, scene_text, optimizer_settings, {});
}

TrajectoryFrames frames_of(const RolloutResult& rollout) {
  TrajectoryFrames frames;
  frames.rows = rollout.grid.rows;
  frames.cols = rollout.grid.cols;
  frames.times = rollout.times;
  frames.positions = rollout.positions;
  return frames;
}

namespace {

// The frames of the mesh stored as mesh_<k>_vertices (a dataset of the file) and mesh_<k>_triangles.
std::vector<TriangleMesh> stored_frames(const Hdf5File& file, const std::string& vertices_name) {
  const std::string triangles_name = vertices_name.substr(0, vertices_name.size() - 8) + "triangles";
  const std::vector<hsize_t> v = file.dims(vertices_name), t = file.dims(triangles_name);
  require(v.size() == 3 && v[2] == 3 && v[0] > 0, file.path(), vertices_name + " is not [frames, vertices, 3]");
  require(t.size() == 2 && t[1] == 3, file.path(), triangles_name + " is not [triangles, 3]");
  const std::vector<double> vertices = file.read_doubles(vertices_name);
  const std::vector<int> triangles = file.read_ints(triangles_name);
  std::vector<TriangleMesh> frames(v[0]);
  for (hsize_t f = 0; f < v[0]; ++f) {
    for (hsize_t k = 0; k < v[1]; ++k) frames[f].vertices.emplace_back(&vertices[3 * (f * v[1] + k)]);
    for (hsize_t k = 0; k < t[0]; ++k)
      frames[f].triangles.push_back({triangles[3 * k], triangles[3 * k + 1], triangles[3 * k + 2]});
  }
  return frames;
}

// The meshes a rollout stores (write_meshes), by their sources.
MeshFrames stored_meshes(const Hdf5File& file) {
  MeshFrames meshes;
  for (const std::string& name : file.names()) {
    static const std::regex vertices("mesh_[0-9]+_vertices");
    if (std::regex_match(name, vertices))
      meshes.emplace(file.string_attribute("source", name), stored_frames(file, name));
  }
  return meshes;
}

}  // namespace

Scene read_rollout_scene(const std::string& path) {
  const Hdf5File file(path, Hdf5File::Mode::Read);
  require(file.has_attribute("scene"), path, "no 'scene' attribute: not an fnopt rollout");
  const StoredMeshes meshes(stored_meshes(file));
  return load_scene_text(file.string_attribute("scene"), path + " (scene attribute)");
}

RolloutProvenance read_rollout_provenance(const std::string& path) {
  const Hdf5File file(path, Hdf5File::Mode::Read);
  auto text = [&](const char* name) { return file.has_attribute(name) ? file.string_attribute(name) : std::string(); };
  return {text("optimizer"), text("fnopt_version"), text("divergence")};
}

}  // namespace fnopt
