#pragma once
// The per-vertex values the viewer colours the cloth by (docs/design.md §11), one float per
// vertex and frame, [T, R*C], computed on the server so that the page only maps them to colours.
#include <vector>

#include <fnopt/simulation/rollout_file.hpp>

namespace fnopt {

// Edge strain: per vertex, the largest |e| / L - 1 over its grid edges (right, left, up, down),
// L the edge's rest length from `rest` (3 floats per vertex). The largest value of a frame is
// the frame's max_edge_strain (cloth/strain.hpp) when the rest grid has spacing h.
std::vector<float> vertex_strain(const TrajectoryFrames& frames, const std::vector<float>& rest);

// Distance [m] from each vertex to the reference at the same time. The reference is
// interpolated linearly between its two frames around that time (ARCSim files keep every second
// step) and, if its grid differs, resampled bilinearly at this grid's rest positions (the same
// material point, cloth/grid_resampling.hpp). NaN for frames outside the reference's time span
// (a reference that diverged early, say). Throws Error for a grid under 3 x 3.
std::vector<float> vertex_distance(const TrajectoryFrames& frames, const TrajectoryFrames& reference);

}  // namespace fnopt
