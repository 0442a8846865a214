#pragma once
// How close a rollout's cloth came to itself (docs/design.md §14): over every frame, the smallest
// distance between vertex-disjoint primitives of the cloth (a vertex and a triangle not holding
// it, two edges sharing no vertex), on the frames as stored and with code separate from the
// self-contact barrier's (metrics/surface_distance.hpp). A flat cloth holds such pairs h/sqrt(2)
// apart (a vertex and the far triangle of its cell's neighbour); folded layers come closer, and
// with self-contact never closer than its thickness (up to the float storage of the frames).
#include <vector>

#include <fnopt/io/trajectory_frames.hpp>

namespace fnopt {

// The smallest such distance of each frame [m]; +inf for a grid without such a pair.
std::vector<double> cloth_distance_per_frame(const TrajectoryFrames& frames);
// The smallest over the frames.
double min_cloth_distance(const TrajectoryFrames& frames);

}  // namespace fnopt
