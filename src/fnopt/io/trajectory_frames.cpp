#include <fnopt/io/trajectory_frames.hpp>

#include <fnopt/io/hdf5_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

TrajectoryFrames read_trajectory_frames(const std::string& path) {
  const Hdf5File file(path, Hdf5File::Mode::Read);
  require(file.has("positions"), path, "no 'positions' dataset: not an fnopt rollout or ARCSim file");
  require(file.has("times_s"), path, "no 'times_s' dataset: not an fnopt rollout or ARCSim file");
  const auto dims = file.dims("positions");
  require(dims.size() == 4 && dims[3] == 3 && dims[0] > 0, path, "'positions' must have shape [T, R, C, 3]");
  TrajectoryFrames frames;
  frames.rows = static_cast<int>(dims[1]);
  frames.cols = static_cast<int>(dims[2]);
  frames.times = file.read_doubles("times_s");
  require(frames.times.size() == dims[0], path, "'times_s' and 'positions' disagree on the frame count");
  const std::vector<float> all = file.read_floats("positions");
  const std::size_t per_frame = dims[1] * dims[2] * 3;
  for (std::size_t t = 0; t < dims[0]; ++t)
    frames.positions.push_back(Eigen::Map<const Eigen::VectorXf>(&all[t * per_frame], per_frame));
  return frames;
}

}  // namespace fnopt
