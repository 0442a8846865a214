#include "method.hpp"

namespace fnopt::python {

MethodRun method_run(const Scene& scene, const std::string& optimizer, int iters, const py::object& model,
                     const py::object& lr, bool gd_curvature_scaled, bool warm_start) {
  OptimizerChoice choice;
  choice.name = optimizer;
  choice.iterations = iters;
  if (!model.is_none()) choice.model = py::str(model).cast<std::string>();
  if (!lr.is_none()) choice.learning_rate = lr.cast<double>();
  choice.gd_curvature_scaled = gd_curvature_scaled;
  MethodRun run;
  run.optimizer = choice.make();
  choice.check_grid(scene.rows, scene.cols);
  run.options.solve = choice.solve_options();
  run.options.warm_start = warm_start;
  return run;
}

}  // namespace fnopt::python
