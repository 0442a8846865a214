#pragma once
// The frames of a trajectory file: an fnopt rollout (simulation/rollout_file.hpp) or an ARCSim
// reference (../shared/data/arcsim/README.md), which share the layout
//   positions  float32 [T, R, C, 3]   vertex (i, j) of frame t
//   times_s    float64 [T]
// so that one reader serves both, and the metrics compare any two of them.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace fnopt {

struct TrajectoryFrames {
  int rows = 0;
  int cols = 0;
  std::vector<double> times;               // [s]
  std::vector<Eigen::VectorXf> positions;  // per frame, 3 floats per vertex, vertex i*cols + j
};

// Throws Error naming the file for anything missing or inconsistent.
TrajectoryFrames read_trajectory_frames(const std::string& path);

}  // namespace fnopt
