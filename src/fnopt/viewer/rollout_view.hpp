#pragma once
// A rollout file as the viewer shows it (docs/design.md §11): an fnopt rollout or an ARCSim
// reference file, flattened into the arrays the page draws, with its per-vertex colours and the
// per-step series it plots. Loaded whole: 100x100 x 391 frames is ~47 MB of positions.
#include <string>
#include <utility>
#include <vector>

namespace fnopt {

// An obstacle as the page draws it (docs/design.md §14): its shape's numbers at t = 0 and its
// translation at every frame. A mesh's triangles are sent once, and its vertices once or, for an
// animated mesh, once per frame; the page draws frame f's vertices (the only ones if there is one)
// translated by offsets[f], so a static or rigidly moving mesh costs no more than its OBJ.
struct ObstacleView {
  std::string shape;            // "plane", "sphere", "box", "capsule" or "mesh"
  std::vector<double> point;    // plane point, sphere/box centre, capsule end a, mesh origin
  std::vector<double> axis;     // plane unit normal, box size, capsule end b; zero for a mesh
  double radius = 0.0;          // sphere/capsule radius, box rounding
  std::vector<float> offsets;   // [T, 3], m
  std::vector<int> triangles;   // a mesh's [F, 3] vertex indices; empty for an analytic shape
  int vertex_count = 0;         // a mesh's V
  std::vector<float> vertices;  // a mesh's [K, V, 3] without offsets, m: K = 1, or T if animated

  int vertex_frames() const { return vertex_count ? static_cast<int>(vertices.size()) / (3 * vertex_count) : 0; }
};

struct RolloutView {
  std::string name;        // the file's name, for the page's title
  std::string kind;        // "fnopt rollout" or "ARCSim-layout file"
  std::string optimizer;   // an fnopt rollout's optimizer settings, "" otherwise
  std::string divergence;  // why it diverged, "" if it did not
  int rows = 0, cols = 0;
  std::vector<double> times;     // [T], s
  std::vector<float> positions;  // [T, R*C, 3], m
  std::vector<int> faces;        // [F, 3] vertex indices
  int handle_count = 0;
  std::vector<float> handle_positions;  // [T, H, 3] prescribed targets, m
  // The per-step datasets present (step_max_strain, step_energy, step_iterations, step_wall_ms
  // of fnopt rollouts; none in ARCSim files), each [T-1], step k ending at times[k+1].
  std::vector<std::pair<std::string, std::vector<double>>> series;
  std::vector<float> strain;    // [T, R*C] (vertex_scalars.hpp)
  std::string reference_name;   // "" without a reference
  std::vector<float> distance;  // [T, R*C], m; empty without a reference
  std::vector<ObstacleView> obstacles;  // an fnopt rollout's scene's, posed at each frame's time

  int frames() const { return static_cast<int>(times.size()); }
  int vertices() const { return rows * cols; }
};

// Reads `path` (and `reference_path` for the distances, "" for none). Throws Error naming the
// file for a missing or unreadable file, one without positions, or inconsistent datasets.
RolloutView load_rollout_view(const std::string& path, const std::string& reference_path = "");

// Everything but the large arrays, as the page's /meta endpoint sends it: sizes, times, handles,
// series, the colour ranges (largest strain and distance), the provenance texts and the obstacles
// (a mesh's sizes only: its arrays are endpoints of their own).
std::string rollout_metadata_json(const RolloutView& view);

}  // namespace fnopt
