#include <fnopt/metrics/trajectory_error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/cloth/strain.hpp>

namespace fnopt {
namespace {

double mean_of(const std::vector<double>& values) {
  if (values.empty()) return std::nan("");
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / values.size();
}

// A grid object for the triangles and strain of a trajectory (the spacing only matters for strain).
Grid grid_of(const TrajectoryFrames& frames, double spacing) {
  Grid grid;
  grid.rows = frames.rows;
  grid.cols = frames.cols;
  grid.spacing = spacing > 0.0 ? spacing : 1.0;
  return grid;
}

}  // namespace

double relative_frame_error(const Eigen::VectorXf& positions, const Eigen::VectorXf& reference) {
  const double denominator = reference.cast<double>().norm();
  if (!(denominator > 0.0)) return std::nan("");
  return (positions.cast<double>() - reference.cast<double>()).norm() / denominator;
}

double max_strain_over_frames(const TrajectoryFrames& frames, double spacing) {
  const Grid grid = grid_of(frames, spacing);
  double strain = 0.0;
  for (const auto& frame : frames.positions) {
    const double s = max_edge_strain(grid, frame.cast<double>());
    strain = std::isfinite(s) ? std::max(strain, s) : INFINITY;
  }
  return strain;
}

std::string TrajectoryComparison::describe_matching() const {
  char text[200];
  if (matches.empty()) {
    std::snprintf(text, sizeof text, "no frames at matching times (reference %d frames, rollout %d frames)",
                  reference_frames, rollout_frames);
  } else {
    std::snprintf(text, sizeof text,
                  "%zu of %d reference frames matched at t = %.4g ... %.4g s (rollout %d frames, %d unmatched)",
                  matches.size(), reference_frames, matches.front().time, matches.back().time, rollout_frames,
                  rollout_frames - static_cast<int>(matches.size()));
  }
  return text;
}

TrajectoryComparison compare_trajectories(const TrajectoryFrames& reference, const TrajectoryFrames& rollout,
                                          double rollout_spacing, const TrajectoryComparisonOptions& options) {
  TrajectoryComparison result;
  result.matches = match_frames(reference.times, rollout.times, options.time_tolerance);
  result.reference_frames = static_cast<int>(reference.positions.size());
  result.rollout_frames = static_cast<int>(rollout.positions.size());
  result.correspondence = reference.rows == rollout.rows && reference.cols == rollout.cols;
  const Triangles reference_triangles = grid_of(reference, 1.0).triangles();
  const Triangles rollout_triangles = grid_of(rollout, 1.0).triangles();
  const int stride = std::max(1, options.chamfer_stride);
  for (std::size_t k = 0; k < result.matches.size(); ++k) {
    const FrameMatch& match = result.matches[k];
    const Eigen::VectorXf& x = rollout.positions[match.rollout];
    const Eigen::VectorXf& x_ref = reference.positions[match.reference];
    if (result.correspondence) result.e3d_per_frame.push_back(relative_frame_error(x, x_ref));
    if (options.chamfer_enabled && k % stride == 0)
      result.chamfer_per_frame.push_back(mesh_chamfer_distance(
          x.cast<double>(), rollout_triangles, x_ref.cast<double>(), reference_triangles, options.chamfer));
  }
  result.chamfer = mean_of(result.chamfer_per_frame);
  result.e3d = mean_of(result.e3d_per_frame);
  result.max_strain = rollout_spacing > 0.0 ? max_strain_over_frames(rollout, rollout_spacing) : std::nan("");
  return result;
}

}  // namespace fnopt
