#pragma once
// Pairing the frames of two trajectories saved at different rates: ARCSim files store 196
// frames every 1/30 s, fnopt rollouts every step (1/60 s). Metrics compare frames at matching
// times only; a frame of either side with no partner within the tolerance is left out (e.g.
// every second fnopt frame, or the frames after a rollout diverged).
#include <vector>

namespace fnopt {

struct FrameMatch {
  int reference = 0;  // frame index in the reference
  int rollout = 0;    // frame index in the rollout
  double time = 0.0;  // the reference frame's time [s]
};

// Frames whose times differ by at most `tolerance` [s]; tolerance <= 0 uses 1 % of the smallest
// spacing between consecutive frames of either trajectory (1e-9 s if both have one frame).
// Times must be non-decreasing (checked: Error otherwise). Each frame is used at most once.
std::vector<FrameMatch> match_frames(const std::vector<double>& reference_times,
                                     const std::vector<double>& rollout_times, double tolerance = 0.0);

}  // namespace fnopt
