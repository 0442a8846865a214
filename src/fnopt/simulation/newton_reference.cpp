#include <fnopt/simulation/newton_reference.hpp>

#include <filesystem>

#include <fnopt/baselines/newton.hpp>
#include <fnopt/util/fnv_hash.hpp>
#include <fnopt/util/parse_text.hpp>
#include <fnopt/version.hpp>

namespace fnopt {

std::string newton_reference_path(const std::string& directory, const std::string& label, const Scene& scene) {
  return newton_reference_path(directory, label, scene, NewtonOptimizer{}.settings());
}

std::string newton_reference_path(const std::string& directory, const std::string& label, const Scene& scene,
                                  const std::string& solver_settings) {
  const InnerSolveOptions options = NewtonOptimizer::reference_solve_options();
  Fnv1aHash hash;
  hash.add(to_scene_text(scene) + "\n" + solver_settings + "\ntol=" +
           number_text(options.relative_tolerance) + " accel_tol=" + number_text(options.acceleration_tolerance) +
           " max=" + std::to_string(options.max_iterations) + "\n" + FNOPT_VERSION);
  return (std::filesystem::path(directory) / ("newton_reference_" + label + "_" + hash.hex() + ".h5")).string();
}

}  // namespace fnopt
