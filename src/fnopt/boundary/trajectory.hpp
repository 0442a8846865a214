#pragma once
// Handle trajectories: where each handle is at time t (docs/design.md §3, §7, §10).
#include <memory>
#include <string>
#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt {

class HandleTrajectory {
 public:
  virtual ~HandleTrajectory() = default;
  // Position [m] of handle k (its index in the HandleSet) at time t [s].
  virtual Vec3 position(int k, double t) const = 0;
  virtual int handle_count() const = 0;
};

// The fifteen benchmark motions with the exact formulas of ../shared/data/arcsim/README.md
// (xy_v2, ..., rot_h1_opp) and "static". `rest` holds the handles' positions at t = 0.
// Translations move every handle by 1 m * p(t) * d/|d|; rot_hK keeps handle K fixed and turns
// every other handle about the vertical axis through it. `speed` (alpha > 0) plays the motion
// alpha times faster: the position at time t is the formula's at alpha*t.
// Throws Error("motion", "...") for an unknown name or a rot_h1 with fewer than 2 handles, and
// Error("speed", "...") for a speed that is not positive and finite.
std::unique_ptr<HandleTrajectory> make_motion(const std::string& name, std::vector<Vec3> rest, double speed = 1.0);

// Replays a CSV of handle positions: a header with t_s and hK_x,hK_y,hK_z for each handle K
// (other columns ignored), rows in strictly increasing time, linear interpolation between rows,
// held constant before the first and after the last row; `speed` replays it alpha times faster.
// A file of several motions (../shared/data/arcsim/motions.csv) has a `motion` column: "path#NAME"
// replays the rows whose motion is NAME, and such a file without "#NAME" is rejected when it holds
// more than one motion. Throws Error("trajectory", "<path>: ...") for an unreadable file, a missing
// column, columns for more handles than `handle_count`, a row of the wrong width, a non-numeric
// or non-finite value, times that do not increase, no data rows, or an unknown or missing #NAME.
std::unique_ptr<HandleTrajectory> load_trajectory_csv(const std::string& path, int handle_count, double speed = 1.0);

std::vector<std::string> benchmark_motion_names();  // the fifteen of the benchmark
std::vector<std::string> motion_names();            // the fifteen, then "static"

// The unit profile p(t) of every benchmark motion, with c(u) = (1 - cos(pi u))/2: 0 until
// 0.5 s, out by c(t - 0.5) until 1.5 s, back by 1 - c(t - 1.5) until 2.5 s, out again by
// c(t - 2.5) until 3.5 s, then held at 1.
double motion_profile(double t);

}  // namespace fnopt
