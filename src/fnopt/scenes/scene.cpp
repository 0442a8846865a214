#include <fnopt/scenes/scene.hpp>

#include <cmath>

#include <fnopt/contact/mesh_contact_term.hpp>
#include <fnopt/scenes/scene_checks.hpp>
#include <fnopt/util/memory_limit.hpp>

namespace fnopt {
namespace {

// An explicit vertex list beats the preset.
HandleSet scene_handles(const Scene& scene, const Grid& grid) {
  if (!scene.handle_vertices.empty()) return handle_vertices_from_list(grid, scene.handle_vertices);
  return handle_preset(grid, scene.handles);
}

std::vector<Vec3> rest_positions_of(const VecX& rest, const HandleSet& handles) {
  std::vector<Vec3> positions;
  for (int v : handles.vertices) positions.push_back(vertex(rest, v));
  return positions;
}

}  // namespace

void Scene::validate() const {
  scene_checks::grid_extent("rows", rows);
  scene_checks::grid_extent("cols", cols);
  scene_checks::positive("size", size, "length in metres");
  scene_checks::positive("dt", dt, "time step in seconds");
  scene_checks::frame_count(frames);
  scene_checks::fits_in_memory(rows, cols, frames, usable_memory_bytes());
  scene_checks::positive("speed", speed, "factor");
  scene_checks::gravity(gravity);
  material.validate();
  // Both names are checked even when an explicit list or a CSV overrides them: a typo in a
  // field that happens to be unused is still a typo.
  scene_checks::handle_preset_name(handles);
  scene_checks::motion_name(motion);
  require(grid_units_of == 0 || grid_units_of >= 3, "grid-units-of", "must be 0 (off) or a grid of at least 3");
  const Grid grid = Grid::make(rows, cols, size);
  const Scene applied = with_grid_units_applied(*this);
  scene_checks::grid_units(grid, applied.material, dt, applied.gravity);
  const HandleSet handle_set = scene_handles(*this, grid);
  // A named motion is cheap to build and checks itself against the handle count (rot_h1 needs
  // two handles); a CSV is only opened by resolve().
  if (trajectory.empty()) make_motion(motion, std::vector<Vec3>(handle_set.vertices.size()), speed);
  require(std::isfinite(let_go), "let-go", "must be a time in seconds");
  if (self_contact_enabled(*this)) self_contact_params.validate_for(grid);
  if (obstacles.empty()) return;
  try {
    contact.validate();
  } catch (const Error& e) {  // named as the user set it (contact-thickness, not contact.thickness)
    const std::string key = e.field() == "contact.range" ? "contact-range" : "contact-" + e.field().substr(8);
    throw Error(key, e.problem());
  }
  const VecX rest = placed_rest_positions(grid, placement);
  refuse_mesh_start(grid, rest);
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    if (obstacles[k].is_mesh()) continue;
    const Vec3 offset = obstacles[k].offset(0.0);
    for (int v = 0; v < grid.vertex_count(); ++v)
      if (!(obstacles[k].distance(vertex(rest, v), offset) > contact.thickness))
        throw Error("obstacle", "obstacle " + std::to_string(k + 1) + ": the cloth starts inside it at vertex (" +
                                    std::to_string(v / grid.cols) + "," + std::to_string(v % grid.cols) + ")");
  }
}

void Scene::refuse_mesh_start(const Grid& grid, const VecX& rest) const {
  std::vector<Obstacle> meshes;
  std::vector<int> number;  // each mesh's place in the scene's list, from 1
  for (std::size_t k = 0; k < obstacles.size(); ++k)
    if (obstacles[k].is_mesh()) meshes.push_back(obstacles[k]), number.push_back(static_cast<int>(k) + 1);
  if (meshes.empty()) return;
  const MeshContactTerm term(grid, meshes, contact);  // posed at t = 0
  auto vertex_name = [&](int v) { return "(" + std::to_string(v / grid.cols) + "," + std::to_string(v % grid.cols) + ")"; };
  MeshContactPair pair{};
  if (term.closest_pair(rest, pair) <= contact.thickness) {
    const int owner = pair.kind == MeshContactPair::Kind::MeshPointClothTriangle ? term.mesh_owner_of_vertex(pair.mesh)
                      : pair.kind == MeshContactPair::Kind::ClothPointMeshTriangle
                          ? term.mesh_owner_of_triangle(pair.mesh)
                          : term.mesh_owner_of_edge(pair.mesh);
    std::string what;
    if (pair.kind == MeshContactPair::Kind::ClothPointMeshTriangle)
      what = "vertex " + vertex_name(pair.cloth) + " is within the thickness of its triangle " + std::to_string(pair.mesh - term.first_triangle(owner));
    else if (pair.kind == MeshContactPair::Kind::MeshPointClothTriangle)
      what = "its vertex " + std::to_string(pair.mesh - term.first_vertex(owner)) + " is within the thickness of the cloth triangle at " +
             vertex_name(term.cloth_triangles()[pair.cloth][0]);
    else
      what = "the cloth edge at " + vertex_name(term.cloth_edges()[pair.cloth][0]) + " is within the thickness of its edge " +
             std::to_string(pair.mesh - term.first_edge(owner));
    throw Error("obstacle", "obstacle " + std::to_string(number[owner]) + ": the cloth starts through it: " + what);
  }
  for (int v = 0; v < grid.vertex_count(); ++v) {
    const int inside = term.enclosing_mesh(rest, v);
    if (inside >= 0)
      throw Error("obstacle", "obstacle " + std::to_string(number[inside]) + ": the cloth starts inside it at vertex " +
                                  vertex_name(v));
  }
}

VecX placed_rest_positions(const Grid& grid, Placement placement) {
  VecX rest = grid.rest_positions();
  if (placement == Placement::Vertical) return rest;
  const double width = (grid.cols - 1) * grid.spacing, height = (grid.rows - 1) * grid.spacing;
  for (int v = 0; v < grid.vertex_count(); ++v) {
    const Vec3 p = vertex(rest, v);  // (j h, 0, -i h)
    vertex(rest, v) = Vec3(p.x() - 0.5 * width, p.z() + 0.5 * height, 0.0);
  }
  return rest;
}

std::string placement_name(Placement placement) {
  return placement == Placement::Horizontal ? "horizontal" : "vertical";
}

namespace {

bool folding_preset(const Scene& scene) {
  return scene.handle_vertices.empty() && (scene.handles == "corner-center" || scene.handles == "single-mid-edge");
}

// On or Off as given; Auto as `automatic` decides.
bool decided(AutoSwitch setting, bool automatic) {
  return setting == AutoSwitch::Auto ? automatic : setting == AutoSwitch::On;
}

}  // namespace

bool self_contact_enabled(const Scene& scene) {
  const bool released = (scene.handle_vertices.empty() && scene.handles == "none") || scene.let_go >= 0.0;
  return decided(scene.self_contact, released || !scene.obstacles.empty() || folding_preset(scene));
}

std::optional<SelfContactParams> self_contact_of(const Scene& scene) {
  if (!self_contact_enabled(scene)) return std::nullopt;
  return scene.self_contact_params;
}

bool repulsion_enabled(const Scene& scene) {
  return decided(scene.repulsion, folding_preset(scene) && !self_contact_enabled(scene));
}

std::string repulsion_mode_name(RepulsionMode mode) {
  switch (mode) {
    case RepulsionMode::On:
      return "true";
    case RepulsionMode::Off:
      return "false";
    case RepulsionMode::Auto:
      break;
  }
  return "auto";
}

void resolve_repulsion(Scene& scene) { scene.material.repulsion = repulsion_enabled(scene); }

Scene with_grid_units_applied(const Scene& scene) {
  if (scene.grid_units_of == 0) return scene;
  Scene applied = scene;
  const double ratio = Grid::make(scene.rows, scene.cols, scene.size).spacing /
                       Grid::make(scene.grid_units_of, scene.grid_units_of, scene.size).spacing;
  // k~_s = k_s dt^2/(rho h^2), k~_b = k_b dt^2/(rho h^4), g~ = |g| dt^2/h (cloth/grid_units.hpp).
  applied.material.stretch *= ratio * ratio;
  applied.material.shear *= ratio * ratio;
  applied.material.bend *= ratio * ratio * ratio * ratio;
  applied.gravity *= ratio;
  applied.grid_units_of = 0;
  return applied;
}

ResolvedScene resolve(const Scene& scene) {
  scene.validate();
  ResolvedScene setup{with_grid_units_applied(scene), Grid::make(scene.rows, scene.cols, scene.size), {}, nullptr, {}};
  setup.rest_positions = placed_rest_positions(setup.grid, scene.placement);
  setup.handles = scene_handles(scene, setup.grid);
  const int handle_count = static_cast<int>(setup.handles.vertices.size());
  setup.trajectory = scene.trajectory.empty()
                         ? make_motion(scene.motion, rest_positions_of(setup.rest_positions, setup.handles), scene.speed)
                         : load_trajectory_csv(scene.trajectory, handle_count, scene.speed);
  require(setup.trajectory->handle_count() == handle_count, "trajectory",
          "moves " + std::to_string(setup.trajectory->handle_count()) + " handle(s), the scene has " +
              std::to_string(handle_count));
  return setup;
}

}  // namespace fnopt
