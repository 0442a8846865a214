#pragma once
// An fnopt optimizer from the Python keywords every entry point takes (optimizer, iters, model,
// lr, gd_curvature_scaled): the command line's OptimizerChoice, with its checks and texts.
#include <fnopt/methods/registry.hpp>

#include "common.hpp"

namespace fnopt::python {

// `model` None: the shipped model; `lr` None or 0: the method's default.
OptimizerChoice optimizer_choice(const std::string& optimizer, int iters, const py::object& model, const py::object& lr,
                                 bool gd_curvature_scaled);

}  // namespace fnopt::python
