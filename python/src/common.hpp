#pragma once
// What every part of the module shares: the conversions between fnopt's vectors (3 values per
// vertex, vertex i * cols + j) and NumPy arrays shaped (rows, cols, 3), and the registration
// functions of the module's parts (docs/api.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <vector>

#include <fnopt/util/types.hpp>

namespace fnopt::python {

namespace py = pybind11;

// A (rows, cols, 3) float64 array of a vector of 3 values per vertex.
py::array_t<double> grid_array(const VecX& values, int rows, int cols);
py::array_t<double> grid_array(const Eigen::VectorXf& values, int rows, int cols);
// (frames, rows, cols, 3) of a sequence of such vectors.
py::array_t<double> frames_array(const std::vector<Eigen::VectorXf>& frames, int rows, int cols);
py::array_t<double> frames_array(const std::vector<VecX>& frames, int rows, int cols);
// The vector of a (rows, cols, 3) or flat (3 rows cols) array-like. Throws Error(field, ...) for
// another shape or a value that is not a number.
VecX grid_vector(const py::handle& values, int rows, int cols, const char* field);
// `count` points of an (count, 3) array-like. Throws Error(field, ...) for another shape.
std::vector<Vec3> point_list(const py::handle& values, std::size_t count, const char* field);
py::array_t<double> point_array(const std::vector<Vec3>& points);

// The record class `name` of python/fnopt/records.py (StepRecord, Material, ...): the module
// returns those frozen dataclasses, built with keyword arguments.
py::object record_type(const char* name);

// The thread count in effect (fnopt.set_threads; the command line's default until then).
int thread_count();

void define_scene(py::module_& m);
void define_step_problem(py::module_& m);
void define_simulator(py::module_& m);
void define_rollouts(py::module_& m);
void define_evaluation(py::module_& m);
void define_adjoint(py::module_& m);

}  // namespace fnopt::python
