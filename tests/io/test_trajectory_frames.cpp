// The frames of a trajectory file: read as written, and refused with the file's name when a
// dataset is missing or the shapes disagree.
#include <gtest/gtest.h>

#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/io/trajectory_frames.hpp>
#include "tests/util/error_message.hpp"
#include "tests/util/temp_dir.hpp"

namespace fnopt {
namespace {

// A file of `frames` frames of a 2 x 3 grid, coordinate k of frame t = 100 t + k.
std::string write_frames(const testing::TempDir& tmp, const std::string& name, int frames, bool with_times) {
  const std::string path = (tmp.path() / name).string();
  Hdf5File file(path, Hdf5File::Mode::Create);
  std::vector<float> positions;
  std::vector<double> times;
  for (int t = 0; t < frames; ++t) {
    times.push_back(0.5 * t);
    for (int k = 0; k < 18; ++k) positions.push_back(100.0f * t + k);
  }
  file.write("positions", {static_cast<hsize_t>(frames), 2, 3, 3}, positions.data());
  if (with_times) file.write("times_s", {static_cast<hsize_t>(frames)}, times.data());
  return path;
}

TEST(TrajectoryFrames, ReadsEveryFrameAsWritten) {
  const testing::TempDir tmp;
  const TrajectoryFrames frames = read_trajectory_frames(write_frames(tmp, "a.h5", 3, true));
  EXPECT_EQ(frames.rows, 2);
  EXPECT_EQ(frames.cols, 3);
  ASSERT_EQ(frames.positions.size(), 3u);
  EXPECT_EQ(frames.times, (std::vector<double>{0.0, 0.5, 1.0}));
  for (int t = 0; t < 3; ++t)
    for (int k = 0; k < 18; ++k) EXPECT_EQ(frames.positions[t][k], 100.0f * t + k);
}

TEST(TrajectoryFrames, ANonTrajectoryFileIsRefusedByName) {
  const testing::TempDir tmp;
  const std::string path = write_frames(tmp, "no-times.h5", 2, false);
  EXPECT_TRUE(testing::throws_error([&] { read_trajectory_frames(path); }, path + ": no 'times_s' dataset"));
}

}  // namespace
}  // namespace fnopt
