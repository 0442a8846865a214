#include <fnopt/io/obj_file.hpp>

#include <fstream>

#include <fnopt/util/atomic_file.hpp>

namespace fnopt {

void write_obj_file(const std::string& path, const Grid& grid, const Eigen::VectorXf& positions) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary);
    if (!out) throw Error(path + ": cannot write the OBJ file");
    for (int k = 0; k < grid.vertex_count(); ++k)
      out << "v " << positions[3 * k] << ' ' << positions[3 * k + 1] << ' ' << positions[3 * k + 2] << '\n';
    const auto faces = grid.triangles();
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      out << "f " << faces(f, 0) + 1 << ' ' << faces(f, 1) + 1 << ' ' << faces(f, 2) + 1 << '\n';
    if (!out) throw Error(path + ": cannot write the OBJ file");
  });
}

}  // namespace fnopt
