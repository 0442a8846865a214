#pragma once
// Comparing a rollout with a reference trajectory (docs/design.md §8), at matching times
// (frame_matching.hpp):
//  - e_3D (the paper's Table 6.2 metric, after Sidhu et al. 2020): per frame
//    ||X - X_ref||_F / ||X_ref||_F over the vertices (vertex k of one is vertex k of the other,
//    so both must have the same rows and cols), averaged over frames; reported x 10^2.
//  - e_CD (chamfer.hpp) per frame, averaged over frames; works across resolutions; x 10^3.
//  - the rollout's largest edge strain over its frames.
#include <string>
#include <vector>

#include <fnopt/io/trajectory_frames.hpp>
#include <fnopt/metrics/chamfer.hpp>
#include <fnopt/metrics/frame_matching.hpp>

namespace fnopt {

// The largest edge strain over a trajectory's frames, its rest edge length `spacing` (+inf once a
// frame is not finite).
double max_strain_over_frames(const TrajectoryFrames& frames, double spacing);

// ||X - X_ref||_F / ||X_ref||_F of one frame (NaN if the reference is all zero).
double relative_frame_error(const Eigen::VectorXf& positions, const Eigen::VectorXf& reference);

struct TrajectoryComparisonOptions {
  ChamferOptions chamfer;
  bool chamfer_enabled = true;  // e_CD is the costly part (10^4 samples and a k-d tree per frame)
  int chamfer_stride = 1;       // e_CD on every k-th matched frame only (e_3D uses all)
  double time_tolerance = 0.0;  // see match_frames
};

struct TrajectoryComparison {
  std::vector<FrameMatch> matches;
  int reference_frames = 0, rollout_frames = 0;
  bool correspondence = false;            // same rows x cols: e_3D defined
  std::vector<double> chamfer_per_frame;  // raw (not x 10^3), one per chamfer_stride-th match
  std::vector<double> e3d_per_frame;      // raw (not x 10^2), one per match if correspondence
  double chamfer = 0.0;                   // mean over matches (NaN if none / disabled)
  double e3d = 0.0;                       // mean over matches (NaN if none / no correspondence)
  double max_strain = 0.0;                // the rollout's, over all its frames

  // "196 of 196 reference frames matched (t = 0 ... 6.5 s), rollout 391 frames"
  std::string describe_matching() const;
};

// `rollout_spacing`: rest edge length h of the rollout's grid (for its strain); <= 0 skips it.
TrajectoryComparison compare_trajectories(const TrajectoryFrames& reference, const TrajectoryFrames& rollout,
                                          double rollout_spacing, const TrajectoryComparisonOptions& options = {});

// max over frames and grid edges of |e|/h - 1.
double max_strain_over_frames(const TrajectoryFrames& frames, double spacing);

}  // namespace fnopt
