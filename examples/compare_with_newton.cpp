// A scene, an optimizer by name, its rollout, and how far it lands from the exact (Newton)
// rollout of the same scene: `fnopt compare` in thirty lines.
//   compare_with_newton [OPTIMIZER [ITERS [RES]]]      e.g. compare_with_newton fnopt-ss 10 32
#include <fnopt/learned.hpp>
#include <fnopt/methods/thread_count.hpp>
#include <fnopt/scenes/scene_settings.hpp>
#include <fnopt/studies/compare/step_error.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) try {
  const std::string method = argc > 1 ? argv[1] : "pqn";
  const std::string res = argc > 3 ? argv[3] : "16";
  fnopt::set_thread_count(1);
  const fnopt::Scene scene = fnopt::apply_scene_settings({}, {{"res", res}, {"frames", "60"}, {"motion", "xy_v2"}});
  const fnopt::ResolvedScene resolved = fnopt::resolve(scene);

  fnopt::OptimizerChoice choice;  // the registry: every optimizer by name
  choice.name = method;
  choice.iterations = argc > 2 ? std::stoi(argv[2]) : 10;
  const auto optimizer = choice.make();
  fnopt::RolloutOptions options;
  options.solve = choice.solve_options();
  const fnopt::RolloutResult rollout = fnopt::run_rollout(resolved, *optimizer, options);

  fnopt::NewtonOptimizer newton;
  fnopt::RolloutOptions exact;
  exact.solve = fnopt::NewtonOptimizer::reference_solve_options();
  const fnopt::RolloutResult reference = fnopt::run_rollout(resolved, newton, exact);

  const fnopt::TrajectoryComparison error =
      fnopt::compare_trajectories(fnopt::frames_of(reference), fnopt::frames_of(rollout), resolved.grid.spacing);
  std::printf(
      "%s %d on %dx%d, %d frames: %.2f ms/frame (Newton %.2f), e_CD %.4f x 10^-3, e_3D %.4f x 10^-2 against "
      "Newton, max strain %.1f %%\n",
      method.c_str(), choice.iterations, scene.rows, scene.cols, scene.frames, fnopt::ms_per_frame(rollout),
      fnopt::ms_per_frame(reference), 1e3 * error.chamfer, 1e2 * error.e3d, 100 * error.max_strain);
  return 0;
} catch (const fnopt::Error& e) {
  std::fprintf(stderr, "compare_with_newton: %s\n", e.what());
  return 2;
}
