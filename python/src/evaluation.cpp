// Measuring an optimizer, fnopt's or one written in Python, as `fnopt compare` measures it:
// against a converged Newton rollout of the same scene (docs/design.md §8).
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/compare/step_error.hpp>
#include <fnopt/metrics/trajectory_error.hpp>
#include <fnopt/studies/compare/compare_study.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/flag_names.hpp>
#include <fnopt/util/output_path.hpp>

#include "common.hpp"
#include "method.hpp"
#include "rollouts.hpp"
#include "step_problem.hpp"

namespace fnopt::python {
namespace {

// A Python callable fn(problem, a, iters) -> a as an inner optimizer: called once per time
// step with the whole budget (it loops itself), the GIL held only during the call. Its answer's
// handle entries are ignored (the prescription is kept).
class CallableOptimizer final : public InnerOptimizer {
 public:
  CallableOptimizer(py::function function, int budget) : function_(std::move(function)), budget_(budget) {
    name_ = py::str(py::getattr(function_, "__qualname__", py::str("callable"))).cast<std::string>();
  }
  std::string name() const override { return "python"; }
  std::string settings() const override {
    return "python " + name_ + ", " + std::to_string(budget_) + " iterations per step";
  }
  void begin_step(StepProblem&, const VecX&, double, const VecX&) override {}
  std::optional<SolveStatus> iterate(StepProblem& problem, VecX& a, double& value, VecX& gradient) override {
    {
      py::gil_scoped_acquire gil;
      const auto alive = std::make_shared<bool>(true);
      const int rows = problem.grid().rows, cols = problem.grid().cols;
      const py::object answer = function_(StepProblemView(problem, a, alive), grid_array(a, rows, cols), budget_);
      *alive = false;
      VecX next = grid_vector(answer, rows, cols, "optimizer result");
      for (int v : problem.dirichlet().fixed_vertices()) next.segment<3>(3 * v) = a.segment<3>(3 * v);
      a = next;
    }
    value = problem.value_gradient(a, gradient);
    return SolveStatus::IterationBudget;  // the callable spent the budget
  }

 private:
  py::function function_;
  int budget_;
  std::string name_;
};

// The method of evaluate_optimizer: a callable, or a name with the usual keywords.
MethodRun method_of(const py::object& method, const Scene& scene, int iters, const py::object& model,
                    const py::object& lr, bool gd_curvature_scaled) {
  require(iters >= 1, "iters", "must be a positive iteration budget");
  if (py::isinstance<py::str>(method) || !PyCallable_Check(method.ptr()))
    return method_run(scene, method.cast<std::string>(), iters, model, lr, gd_curvature_scaled, false);
  MethodRun run;
  run.optimizer = std::make_unique<CallableOptimizer>(method, iters);
  run.options.solve = {iters, 0.0};
  return run;
}

py::object evaluate_optimizer(const py::object& method, const Scene& scene, int iters, const py::object& reference,
                              int samples, int cd_stride, int chamfer_samples, const py::object& model,
                              const py::object& lr, bool gd_curvature_scaled) {
  require(samples >= 1, "samples", "must be positive");
  require(cd_stride >= 1, "cd_stride", "must be at least 1");
  const MethodRun m = method_of(method, scene, iters, model, lr, gd_curvature_scaled);
  TrajectoryComparisonOptions compare;
  compare.chamfer.samples = chamfer_samples;
  compare.chamfer.validate();
  compare.chamfer_stride = cd_stride;
  TrajectoryFrames reference_frames;
  if (reference.is_none()) {
    NewtonOptimizer newton;
    RolloutOptions options;
    options.solve = NewtonOptimizer::reference_solve_options();
    reference_frames = frames_of(run_python_rollout(scene, newton, options).result);
  } else {
    reference_frames = frames_from(reference);
  }
  const PyRollout run = run_python_rollout(scene, *m.optimizer, m.options);
  TrajectoryComparison c;
  StepErrorSummary steps;
  {
    py::gil_scoped_release release;
    c = compare_trajectories(reference_frames, frames_of(run.result), run.result.grid.spacing, compare);
    StepErrorBench bench(scene, reference_frames, samples);
    steps = bench.evaluate(*m.optimizer, m.options.solve);
  }
  py::tuple per_step(steps.samples.size());
  for (std::size_t k = 0; k < steps.samples.size(); ++k) per_step[k] = steps.samples[k].error;
  using namespace pybind11::literals;
  // As in compare: a diverged run's trajectory errors are undefined (its frames stop early).
  return record_type("Evaluation")(
      "optimizer"_a = run.settings, "iters"_a = iters, "ms_per_frame"_a = ms_per_frame(run.result),
      "e_cd"_a = run.result.diverged ? NAN : 1e3 * c.chamfer, "e_3d"_a = run.result.diverged ? NAN : 1e2 * c.e3d,
      "step_error_mean"_a = steps.mean, "step_error_median"_a = steps.median, "step_errors"_a = per_step,
      "max_strain"_a = run.result.max_strain(), "frames"_a = static_cast<int>(run.result.positions.size()) - 1,
      "diverged"_a = run.result.diverged, "divergence"_a = run.result.divergence);
}

// fnopt compare's study on the given scenes; its rows (compare.csv) as CompareRow records.
py::list compare(const py::object& scenes, const std::vector<std::string>& optimizers, const std::vector<int>& iters,
                 const py::object& out, const py::object& model, int step_samples, int cd_stride, int chamfer_samples,
                 bool resume) {
  CompareStudy study;
  if (py::isinstance<Scene>(scenes)) {
    study.scenes.push_back(scenes.cast<Scene>());
  } else {
    for (const py::handle scene : scenes) study.scenes.push_back(scene.cast<Scene>());
  }
  study.methods = optimizers;
  study.budgets = iters;
  if (!model.is_none()) study.settings.model = py::str(model).cast<std::string>();
  study.step_samples = step_samples;
  study.cd_stride = cd_stride;
  study.chamfer.samples = chamfer_samples;
  study.resume = resume;
  study.threads = thread_count();
  if (out.is_none()) {
    std::random_device entropy;
    study.out = (std::filesystem::temp_directory_path() / ("fnopt_compare_" + std::to_string(entropy()))).string();
  } else {
    study.out = py::str(out).cast<std::string>();
  }
  study.command_line = "fnopt.compare (Python)";
  with_flag_names({{"compare.scenes", "scenes"},
                   {"compare.methods", "optimizers"},
                   {"compare.out", "out"},
                   {"compare.budgets", "iters"},
                   {"compare.learning_rates", "optimizers"},
                   {"compare.step_samples", "step_samples"},
                   {"compare.cd_stride", "cd_stride"},
                   {"cd-samples", "chamfer_samples"}},
                  [&] { study.validate(); });
  require_writable_directory(study.out, "out");
  {
    py::gil_scoped_release release;
    run_compare_study(study);
  }
  const CsvTable table = CsvTable::read((std::filesystem::path(study.out) / "compare.csv").string());
  const py::object from_cells = record_type("CompareRow").attr("from_cells");
  py::list rows;
  for (const auto& values : table.rows()) {
    py::dict cells;
    for (std::size_t k = 0; k < values.size(); ++k) cells[py::str(table.columns()[k])] = values[k];
    rows.append(from_cells(cells));
  }
  return rows;
}

}  // namespace

void define_evaluation(py::module_& m) {
  m.def("evaluate_optimizer", &evaluate_optimizer, py::arg("optimizer"), py::arg("scene"), py::arg("iters"),
        py::arg("reference") = py::none(), py::arg("samples") = 16, py::arg("cd_stride") = 2,
        py::arg("chamfer_samples") = 10000, py::arg("model") = py::none(), py::arg("lr") = py::none(),
        py::arg("gd_curvature_scaled") = true,
        R"(Measures one optimizer on one scene as ``fnopt compare`` does.

Its rollout is timed and compared with a converged Newton rollout (e_CD, e_3D), and its
per-step error is taken from `samples` states of that reference.

Parameters
----------
optimizer : str or callable
    An optimizer's name, or a Python callable ``fn(problem, a, iters) -> a`` called once per
    time step with the StepProblem, the start a_0 and the budget.
scene : Scene
    The scene, its frames included.
iters : int
    The budget per step.
reference : Rollout or str or os.PathLike, optional
    The converged Newton rollout of the scene (a Rollout or rollout file); default: run now.
samples : int, optional
    Reference states the per-step error is measured from.
cd_stride : int, optional
    e_CD on every k-th frame only.
chamfer_samples : int, optional
    Points sampled on each mesh for e_CD.
model, lr, gd_curvature_scaled
    For a named optimizer, as for `Simulator`.

Returns
-------
Evaluation
    ms_per_frame, e_cd, e_3d, the per-step errors, max strain, frames and divergence.)");
  m.def("compare", &compare, py::arg("scenes"), py::arg("optimizers"), py::arg("iters") = std::vector<int>{10},
        py::arg("out") = py::none(), py::arg("model") = py::none(), py::arg("step_samples") = 16,
        py::arg("cd_stride") = 2, py::arg("chamfer_samples") = 10000, py::arg("resume") = false,
        R"(Runs ``fnopt compare`` on scenes: every optimizer at every budget against the Newton reference.

Parameters
----------
scenes : Scene or list of Scene
    The scenes.
optimizers : list of str
    The optimizers' names (Newton runs to its tolerance).
iters : list of int, optional
    The budgets per step.
out : str or os.PathLike, optional
    Where compare.csv, compare.svg and report.md go; default: a new temporary directory.
model : str or os.PathLike, optional
    The learned optimizers' weights; default: each method's shipped model.
step_samples : int, optional
    Reference states the per-step error is measured from.
cd_stride : int, optional
    e_CD on every k-th frame only.
chamfer_samples : int, optional
    Points sampled on each mesh for e_CD.
resume : bool, optional
    Keep the rows an earlier run left in `out` and run only the missing ones.

Returns
-------
list of CompareRow
    compare.csv's rows, in its order.)");
}

}  // namespace fnopt::python
