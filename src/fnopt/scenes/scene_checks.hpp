#pragma once
// Range checks of single scene fields, shared by Scene::validate and apply_scene_setting so
// that a bad value is reported the same way whether it came from a file line, a flag or code.
// Each throws Error("<field>: <problem>"); NaN fails every one of them.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fnopt/boundary/handles.hpp>
#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/util/types.hpp>

namespace fnopt::scene_checks {

inline void grid_extent(const std::string& field, int count) {
  require(count >= 3, field, "the grid needs at least 3 vertices along each side, got " + std::to_string(count));
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
          "must be three finite numbers in m/s^2, got (" + number_text(g.x()) + ", " + number_text(g.y()) + ", " +
              number_text(g.z()) + ")");
}

// Each field finite and in range can still give a scene that no step can take: in grid units
// (docs/design.md §2, length h, time dt, mass rho h^2) the numbers the solvers work with may
// overflow or underflow to zero (a stretch of 1e300 N/m, a density of 1e-320 kg/m^2, dt = 1e200
// s), and the first step then divides by zero or diverges. A grid-unit number above 1e100 is
// refused too: the solvers square gradients and sum over 10^4-10^6 stencils, which overflows
// from about 1e150, while the stiffest cloth fnopt runs (stretch x1000 at 200^2) is about 3e7.
// Refused before any work, naming the field that carries the overflow.
constexpr double kMaxGridUnits = 1e100;

inline void grid_units(const Grid& grid, const Material& m, double dt, const Vec3& gravity) {
  const double h = grid.spacing, dt2 = dt * dt, mass = m.density * h * h;
  require(std::isnormal(dt2), "dt", number_text(dt) + " s is out of range in grid units: dt^2 = " + number_text(dt2));
  require(std::isnormal(h * h) && std::isnormal(h * h * h * h), "size",
          number_text(grid.spacing) + " m per cell is out of range in grid units: h^4 = " + number_text(h * h * h * h));
  require(std::isnormal(mass), "density",
          number_text(m.density) + " kg/m^2 is out of range in grid units: the mass rho h^2 of a vertex is " +
              number_text(mass) + " kg");
  const GridUnitStiffness units = grid_unit_stiffness(grid, m, dt, gravity.norm());
  const std::string with =
      " (dt " + number_text(dt) + " s, density " + number_text(m.density) + " kg/m^2, h " + number_text(h) + " m)";
  auto finite = [&](const std::string& field, double value, double grid_units, const std::string& unit,
                    const std::string& formula) {
    require(std::isfinite(grid_units) && grid_units <= kMaxGridUnits, field,
            number_text(value) + " " + unit + " overflows in grid units: " + formula + " = " + number_text(grid_units) +
                with + ", above " + number_text(kMaxGridUnits));
  };
  finite("stretch", m.stretch, units.stretch, "N/m", "k_s dt^2 / (rho h^2)");
  finite("shear", m.shear, units.shear, "N/m", "k_sh dt^2 / (rho h^2)");
  finite("bend", m.bend, units.bend, "N m", "k_b dt^2 / (rho h^4)");
  finite("gravity", gravity.norm(), units.gravity, "m/s^2", "|g| dt^2 / h");
  finite("damping", m.damping, m.damping * dt, "1/s", "c dt");
  finite("repulsion-stiffness", m.repulsion_stiffness, m.repulsion_stiffness * dt2 / mass, "N/m",
         "lambda dt^2 / (rho h^2)");
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
