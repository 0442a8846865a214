#pragma once
// An fnopt optimizer and its rollout options from the Python keywords every entry point takes
// (optimizer, iters, model, lr, gd_curvature_scaled, warm_start): the command line's
// OptimizerChoice, with its checks and texts, as `fnopt simulate` builds them.
#include <memory>
#include <string>

#include <fnopt/methods/registry.hpp>
#include <fnopt/simulation/rollout.hpp>

#include "common.hpp"

namespace fnopt::python {

struct MethodRun {
  std::unique_ptr<InnerOptimizer> optimizer;
  RolloutOptions options;  // the method's budget or tolerance
};

// `model` None: the shipped model; `lr` None or 0: the method's default. Throws Error for an
// unknown name, bad settings or a method that cannot run on the scene's grid.
MethodRun method_run(const Scene& scene, const std::string& optimizer, int iters, const py::object& model,
                     const py::object& lr, bool gd_curvature_scaled, bool warm_start);

}  // namespace fnopt::python
