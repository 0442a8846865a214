#pragma once
// Newton reference rollouts cached on disk (compare, the training validation): one file per
// scene, named by a hash of everything the reference depends on: the resolved scene, Newton's
// settings and tolerance, and fnopt's version. A file of another scene, solver or version has
// another name and is never read.
#include <string>

#include <fnopt/scenes/scene.hpp>

namespace fnopt {

// DIR/newton_reference_<label>_<hash>.h5; `label` (e.g. "64_xy_v2") is for people only. The hash
// covers `solver_settings` (NewtonOptimizer::settings(): the reference's, or newton-min's).
std::string newton_reference_path(const std::string& directory, const std::string& label, const Scene& scene,
                                  const std::string& solver_settings);
std::string newton_reference_path(const std::string& directory, const std::string& label, const Scene& scene);

}  // namespace fnopt
