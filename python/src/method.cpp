#include "method.hpp"

namespace fnopt::python {

OptimizerChoice optimizer_choice(const std::string& optimizer, int iters, const py::object& model, const py::object& lr,
                                 bool gd_curvature_scaled) {
  OptimizerChoice choice;
  choice.name = optimizer;
  choice.iterations = iters;
  if (!model.is_none()) choice.model = py::str(model).cast<std::string>();
  if (!lr.is_none()) choice.learning_rate = lr.cast<double>();
  choice.gd_curvature_scaled = gd_curvature_scaled;
  return choice;
}

}  // namespace fnopt::python
