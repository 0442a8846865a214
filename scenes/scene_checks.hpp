#pragma once
// Range checks of single scene fields, shared by Scene::validate and apply_scene_setting so
// that a bad value is reported the same way whether it came from a file line, a flag or code.
// Each throws Error("<field>: <problem>"); NaN fails every one of them.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "boundary/handles.hpp"
#include "util/parse_text.hpp"
#include "boundary/trajectory.hpp"
#include "util/error.hpp"
#include "util/types.hpp"

namespace fnopt::scene_checks {

inline void grid_extent(const std::string& field, int count) {
  require(count >= 3, field, "the grid needs at least 3 vertices along each side, got " +
                                 std::to_string(count));
}

// A rollout keeps every frame's positions (12 bytes per vertex) and its solvers work with a few
// kilobytes per vertex (sparse Hessians and factors: ~1 KB at 100^2; the FNO's hidden
// channels: ~2 KB). A grid whose estimate exceeds the machine's memory is refused up front, with
// its size, rather than failing deep inside an allocation.
inline void fits_in_memory(int rows, int cols, int frames, double memory_bytes) {
  const double vertices = static_cast<double>(rows) * cols;
  const double needed = vertices * (12.0 * (frames + 1) + 4096.0);
  require(needed <= memory_bytes, "res",
          "a " + std::to_string(rows) + "x" + std::to_string(cols) + " grid (" + number_text(vertices) +
              " vertices) over " + std::to_string(frames) + " frames needs about " + number_text(needed / 1e9) +
              " GB, more than this machine's " + number_text(memory_bytes / 1e9) + " GB");
}

inline void positive(const std::string& field, double value, const std::string& what) {
  require(std::isfinite(value) && value > 0.0, field,
          "must be a positive finite " + what + ", got " + number_text(value));
}

inline void frame_count(int frames) {
  require(frames >= 1, "frames", "must be at least 1, got " + std::to_string(frames));
}

inline void gravity(const Vec3& g) {
  require(g.allFinite(), "gravity",
          "must be three finite numbers in m/s^2, got (" + number_text(g.x()) + ", " +
              number_text(g.y()) + ", " + number_text(g.z()) + ")");
}

inline void handle_preset_name(const std::string& name) {
  const auto names = handle_preset_names();
  require(std::find(names.begin(), names.end(), name) != names.end(), "handles",
          "unknown preset '" + name + "' (valid: " + joined(names) + ")");
}

inline void motion_name(const std::string& name) {
  const auto names = motion_names();
  require(std::find(names.begin(), names.end(), name) != names.end(), "motion",
          "unknown motion '" + name + "' (valid: " + joined(names) + ")");
}

}  // namespace fnopt::scene_checks
