// The extension module fnopt._fnopt behind the package `fnopt` (python/fnopt/__init__.py).
// Every fnopt::Error (a bad scene field, file, model or setting) is raised as fnopt.Error, a
// ValueError, with the command line's one-line text.
#include <pybind11/stl.h>

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

py::object record_type(const char* name) { return py::module_::import("fnopt.records").attr(name); }

}  // namespace fnopt::python

PYBIND11_MODULE(_fnopt, m) {
  namespace py = pybind11;
  using namespace fnopt::python;
  m.doc() = "fnopt: cloth on regular grids, classical and learned inner optimizers (docs/api.md)";
  m.attr("__version__") = FNOPT_VERSION;
  static py::exception<fnopt::Error> error(m, "Error", PyExc_ValueError);
  error.attr("__doc__") = R"(Everything a user can cause: a bad scene field, file, model or setting.

A ValueError whose text is the command line's one line, ``field: problem``.)";
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
      py::arg("threads"), R"(Sets the OpenMP and LibTorch thread count, as ``--threads`` does.

Parameters
----------
threads : int
    The thread count; 0 for the default ($OMP_NUM_THREADS, else 1).

Returns
-------
int
    The thread count now in effect.)");
  m.def("threads", &thread_count, R"(The OpenMP and LibTorch thread count in effect.

Returns
-------
int
    The count set by `set_threads`, or the default ($OMP_NUM_THREADS, else 1).)");
  m.def("optimizer_names", &fnopt::optimizer_list, py::arg("ablations") = true,
        R"(Every optimizer's name, as ``fnopt --help`` lists them.

Besides these, METHOD-interpK runs METHOD on a K-vertex coarse grid and interpolates
(``newton-interp32``).

Parameters
----------
ablations : bool
    Also the ablation variants of the learned optimizer (fnopt-plain, fnopt-ls, fnopt-ss-32,
    fnopt-pqn), which ``--help`` lists apart.

Returns
-------
list of str
    The names, in the registry's order.)");
  m.def("shipped_model_path", &fnopt::shipped_model_path,
        R"(The learned model trained at 32^2 only: the default of every learned method but fnopt-ss.

Returns
-------
str
    The path of ``fnopt-32.pt`` (installed under share/fnopt/models, else the source tree's).)");
  m.def("multires_model_path", &fnopt::multires_model_path, R"(fnopt-ss's default model, trained on 32^2 to 100^2 grids.

Returns
-------
str
    The path of ``fnopt-multires.pt`` (installed under share/fnopt/models, else the source tree's).)");
  define_scene(m);
  define_step_problem(m);
  define_simulator(m);
  define_rollouts(m);
  define_evaluation(m);
  define_adjoint(m);
}
