// The extension module fnopt._fnopt behind the package `fnopt` (python/fnopt/__init__.py).
// Every fnopt::Error (a bad scene field, file, model or setting) is raised as fnopt.Error, a
// ValueError, with the command line's one-line text.
#include <fnopt/methods/registry.hpp>
#include <fnopt/methods/thread_count.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/version.hpp>

#include "common.hpp"

namespace fnopt::python {
namespace {
int g_threads = 0;
}  // namespace

int thread_count() { return g_threads; }

}  // namespace fnopt::python

PYBIND11_MODULE(_fnopt, m) {
  namespace py = pybind11;
  using namespace fnopt::python;
  m.doc() = "fnopt: cloth on regular grids, classical and learned inner optimizers (docs/api.md)";
  m.attr("__version__") = FNOPT_VERSION;
  static py::exception<fnopt::Error> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const fnopt::Error& e) {
      error(e.what());
    }
  });
  g_threads = fnopt::set_thread_count(0);
  m.def(
      "set_threads",
      [](int threads) {
        fnopt::require(threads >= 0, "threads", "must be a whole number of threads, or 0 for the default");
        g_threads = fnopt::set_thread_count(threads);
        return g_threads;
      },
      py::arg("threads"),
      "Sets the OpenMP and LibTorch thread count, as --threads does (0: $OMP_NUM_THREADS, else 1); returns it");
  m.def("threads", &thread_count, "The thread count in effect");
  m.def("optimizer_names", &fnopt::optimizer_names, "Every optimizer's name, as `fnopt --help` lists them");
  m.def("shipped_model_path", &fnopt::shipped_model_path,
        "The model trained at 32^2 only (the default of every learned method but fnopt-ss)");
  m.def("multires_model_path", &fnopt::multires_model_path, "fnopt-ss's default model, trained on 32^2 to 100^2 grids");
  define_scene(m);
  define_step_problem(m);
  define_simulator(m);
  define_rollouts(m);
  define_evaluation(m);
}
