#pragma once
#include <string>

#include <Eigen/Core>

#include <fnopt/cloth/grid.hpp>

namespace fnopt {

// One frame as a Wavefront OBJ (v lines, then f lines of the grid's triangles, 1-based), for
// Blender and other tools. Written atomically.
void write_obj_file(const std::string& path, const Grid& grid, const Eigen::VectorXf& positions);

}  // namespace fnopt
