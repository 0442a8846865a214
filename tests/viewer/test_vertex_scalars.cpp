// The per-vertex colours: edge strain of a uniformly stretched grid, and the distance to a
// reference across a time resampling (every second frame) and a grid resampling (a finer grid).
#include <gtest/gtest.h>

#include <cmath>

#include <fnopt/cloth/grid.hpp>
#include <fnopt/viewer/vertex_scalars.hpp>

namespace fnopt {
namespace {

// Frames of a rows x cols grid of spacing 1 under x -> (a x + b z t, y + c t, d z) at each time.
TrajectoryFrames affine_frames(int rows, int cols, const std::vector<double>& times, float a, float d) {
  TrajectoryFrames frames;
  frames.rows = rows;
  frames.cols = cols;
  frames.times = times;
  const float spacing_x = 1.0f / (cols - 1), spacing_z = 1.0f / (rows - 1);
  for (const double time : times) {
    const float t = static_cast<float>(time);
    Eigen::VectorXf x(3 * rows * cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) {
        const float u = j * spacing_x, w = -i * spacing_z;
        x.segment<3>(3 * (i * cols + j)) << a * u + 0.3f * w * t, 0.5f * t, d * w;
      }
    frames.positions.push_back(x);
  }
  return frames;
}

TEST(ViewerVertexScalars, StrainOfAStretchedGridIsItsLargestEdgeStretch) {
  const TrajectoryFrames rest = affine_frames(4, 6, {0.0}, 1.0f, 1.0f);
  const std::vector<float> rest_positions(rest.positions[0].data(), rest.positions[0].data() + 3 * 24);
  // Frame 0 at rest; frame 1 stretched 10 % along rows and 20 % down the columns.
  TrajectoryFrames frames = affine_frames(4, 6, {0.0}, 1.0f, 1.0f);
  frames.positions.push_back(affine_frames(4, 6, {0.0}, 1.1f, 1.2f).positions[0]);
  frames.times.push_back(0.1);
  const std::vector<float> strain = vertex_strain(frames, rest_positions);
  ASSERT_EQ(strain.size(), 2u * 24);
  for (int k = 0; k < 24; ++k) {
    EXPECT_NEAR(strain[k], 0.0f, 1e-6);
    EXPECT_NEAR(strain[24 + k], 0.2f, 1e-5);
  }
}

TEST(ViewerVertexScalars, DistanceToAnOffsetReferenceIsTheOffset) {
  const TrajectoryFrames frames = affine_frames(5, 7, {0.0, 0.1, 0.2}, 1.0f, 1.0f);
  TrajectoryFrames reference = frames;
  for (auto& x : reference.positions)
    for (int k = 0; k < 35; ++k) x(3 * k + 1) += 0.01f;
  for (const float d : vertex_distance(frames, reference)) EXPECT_NEAR(d, 0.01f, 1e-6);
}

TEST(ViewerVertexScalars, DistanceMatchesFramesByTimeAndResamplesAnotherGrid) {
  // The reference keeps every second frame, on a grid twice as fine, of the same motion (affine
  // in time and space, so interpolating it is exact); it ends before the rollout does.
  const TrajectoryFrames frames = affine_frames(4, 5, {0.0, 0.05, 0.1, 0.15, 0.2, 0.25}, 1.0f, 1.0f);
  const TrajectoryFrames reference = affine_frames(7, 9, {0.0, 0.1, 0.2}, 1.0f, 1.0f);
  const std::vector<float> distance = vertex_distance(frames, reference);
  ASSERT_EQ(distance.size(), 6u * 20);
  for (int t = 0; t < 5; ++t)
    for (int k = 0; k < 20; ++k) EXPECT_NEAR(distance[t * 20 + k], 0.0f, 1e-5) << "frame " << t << " vertex " << k;
  for (int k = 0; k < 20; ++k) EXPECT_TRUE(std::isnan(distance[5 * 20 + k])) << "past the reference's end";
}

}  // namespace
}  // namespace fnopt
