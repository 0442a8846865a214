#pragma once
// fnopt.Rollout, shared by the rollout functions and the evaluation of optimizers.
#include <string>

#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/simulation/rollout.hpp>

#include "common.hpp"

namespace fnopt::python {

struct PyRollout {
  RolloutResult result;
  Scene scene;            // stored in its file, with its meshes
  std::string settings;   // stored in its file
  std::string optimizer;  // the optimizer's name
};

// A step's record as fnopt.records.StepRecord.
py::object step_record(const StepRecord& record);

// The scene's frames with `optimizer`, the GIL released.
PyRollout run_python_rollout(const Scene& scene, InnerOptimizer& optimizer, const RolloutOptions& options);
// The frames of a Rollout or of a rollout file's path.
TrajectoryFrames frames_from(const py::handle& source);

}  // namespace fnopt::python
