// NumPy arrays of fnopt's vectors and back (common.hpp).
#include "common.hpp"

#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt::python {
namespace {

template <class Vector>
py::array_t<double> to_grid_array(const Vector& values, int rows, int cols) {
  py::array_t<double> array({rows, cols, 3});
  double* out = array.mutable_data();
  for (Eigen::Index k = 0; k < values.size(); ++k) out[k] = static_cast<double>(values[k]);
  return array;
}

template <class Vector>
py::array_t<double> to_frames_array(const std::vector<Vector>& frames, int rows, int cols) {
  const py::ssize_t count = static_cast<py::ssize_t>(frames.size());
  py::array_t<double> array({count, static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols), py::ssize_t{3}});
  double* out = array.mutable_data();
  for (const Vector& frame : frames)
    for (Eigen::Index k = 0; k < frame.size(); ++k) *out++ = static_cast<double>(frame[k]);
  return array;
}

}  // namespace

py::array_t<double> grid_array(const VecX& values, int rows, int cols) { return to_grid_array(values, rows, cols); }

py::array_t<double> grid_array(const Eigen::VectorXf& values, int rows, int cols) {
  return to_grid_array(values, rows, cols);
}

py::array_t<double> frames_array(const std::vector<Eigen::VectorXf>& frames, int rows, int cols) {
  return to_frames_array(frames, rows, cols);
}

py::array_t<double> frames_array(const std::vector<VecX>& frames, int rows, int cols) {
  return to_frames_array(frames, rows, cols);
}

VecX grid_vector(const py::handle& values, int rows, int cols, const char* field) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  require(static_cast<bool>(array), field, "expected an array of numbers");
  const py::ssize_t size = 3 * static_cast<py::ssize_t>(rows) * cols;
  const bool grid_shape = array.ndim() == 3 && array.shape(0) == rows && array.shape(1) == cols && array.shape(2) == 3;
  const bool flat = array.ndim() == 1 && array.shape(0) == size;
  require(grid_shape || flat, field,
          "expected shape (" + std::to_string(rows) + ", " + std::to_string(cols) + ", 3) or (" + std::to_string(size) +
              ",)");
  return Eigen::Map<const VecX>(array.data(), size);
}

std::vector<Vec3> point_list(const py::handle& values, std::size_t count, const char* field) {
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  require(static_cast<bool>(array) && array.ndim() == 2 && array.shape(1) == 3 &&
              static_cast<std::size_t>(array.shape(0)) == count,
          field, "expected shape (" + std::to_string(count) + ", 3)");
  std::vector<Vec3> points(count);
  for (std::size_t k = 0; k < count; ++k) points[k] = Vec3(array.at(k, 0), array.at(k, 1), array.at(k, 2));
  return points;
}

py::array_t<double> point_array(const std::vector<Vec3>& points) {
  py::array_t<double> array({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto out = array.mutable_unchecked<2>();
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int d = 0; d < 3; ++d) out(k, d) = points[k][d];
  return array;
}

}  // namespace fnopt::python
