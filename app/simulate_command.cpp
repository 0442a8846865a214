// fnopt simulate: one rollout of a scene with one inner optimizer, written as HDF5 (and OBJ).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <fnopt/cloth/grid_units.hpp>
#include <fnopt/io/obj_file.hpp>
#include <fnopt/metrics/obstacle_distance.hpp>
#include <fnopt/simulation/rollout_file.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/output_path.hpp>
#include <fnopt/util/progress_bar.hpp>
#include "app/commands.hpp"
#include "app/optimizer_flags.hpp"
#include "app/scene_flags.hpp"
#include "app/threads.hpp"

namespace fnopt::app {
namespace {

struct SimulateFlags {
  SceneFlags scene;
  OptimizerChoice optimizer;
  std::string out = "rollout.h5";
  std::string obj_dir;
  int threads = 0;  // the default: set_thread_count
  bool warm_start = false;
};

void run_simulate(const SimulateFlags& flags) {
  const Scene scene = flags.scene.scene();
  const ResolvedScene resolved = resolve(scene);  // handles and trajectory read now, not after the banner
  const auto optimizer = flags.optimizer.make();
  flags.optimizer.check_grid(scene.rows, scene.cols);
  require_writable_file(flags.out, "out");
  if (!flags.obj_dir.empty()) require_writable_directory(flags.obj_dir, "obj-dir");
  const int threads = set_thread_count(flags.threads);
  RolloutOptions options;
  options.solve = flags.optimizer.solve_options();
  options.warm_start = flags.warm_start;

  std::fprintf(stderr, "fnopt simulate: %dx%d grid, %s handles, %s, %d frames, optimizer %s, %d thread%s\n", scene.rows,
               scene.cols, scene.handle_vertices.empty() ? scene.handles.c_str() : "explicit",
               scene.trajectory.empty() ? ("motion " + scene.motion).c_str() : scene.trajectory.c_str(), scene.frames,
               optimizer->name().c_str(), threads, threads == 1 ? "" : "s");
  std::fprintf(stderr, "%s\n", optimizer->settings().c_str());
  const GridUnitStiffness k =
      grid_unit_stiffness(resolved.grid, resolved.scene.material, scene.dt, resolved.scene.gravity.norm());
  std::fprintf(stderr, "grid units: stretch %.4g, shear %.4g, bend %.4g, gravity %.4g (docs/design.md §2)\n", k.stretch,
               k.shear, k.bend, k.gravity);
  std::fprintf(stderr, "self-repulsion: %s (repulsion = %s), lambda %.4g N/m, delta %.4g h\n",
               scene.material.repulsion ? "on" : "off", repulsion_mode_name(scene.repulsion).c_str(),
               scene.material.repulsion_stiffness, scene.material.repulsion_range);
  std::fprintf(stderr, "self-contact: %s (self-contact = %s), kappa %.4g N/m, dhat %.4g m, thickness %.4g m\n",
               self_contact_enabled(scene) ? "on" : "off", repulsion_mode_name(scene.self_contact).c_str(),
               scene.self_contact_params.stiffness, scene.self_contact_params.range,
               scene.self_contact_params.thickness);
  for (std::size_t k = 0; k < scene.obstacles.size(); ++k)
    std::fprintf(stderr, "obstacle %zu: %s\n", k + 1, scene.obstacles[k].to_text().c_str());
  ProgressBar bar("simulate", scene.frames);
  const RolloutResult rollout = run_rollout(resolved, *optimizer, options, [&](int done, int, const StepRecord& s) {
    char status[96];
    std::snprintf(status, sizeof status, "%.1f ms/step, %d it, strain %.1f%%", s.wall_ms, s.iterations,
                  100 * s.max_strain);
    bar.update(done, status);
  });
  bar.finish();

  write_rollout_file(flags.out, rollout, scene, optimizer->settings());
  if (!flags.obj_dir.empty()) {
    for (std::size_t t = 0; t < rollout.positions.size(); ++t) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04zu.obj", t);
      write_obj_file((std::filesystem::path(flags.obj_dir) / name).string(), rollout.grid, rollout.positions[t]);
    }
  }

  const int converged = rollout.converged_steps();
  int precision_limited = 0, max_iterations = 0;
  for (const auto& s : rollout.steps) {
    precision_limited += s.status == SolveStatus::PrecisionLimit;
    max_iterations = std::max(max_iterations, s.iterations);
  }
  const int steps = static_cast<int>(rollout.steps.size());
  // A method with a tolerance reports how many steps reached it; a fixed budget does not.
  std::string convergence = "fixed budget";
  if (options.solve.to_tolerance()) {
    convergence = std::to_string(converged) + "/" + std::to_string(steps) + " steps converged";
    if (precision_limited > 0) convergence += " (" + std::to_string(precision_limited) + " to the precision of L)";
  }
  std::printf(
      "%s: %d/%d frames, %dx%d, %.1f ms/frame, max edge strain %.1f %%, %.2f iterations/step (max %d), "
      "%s, %s; wrote %s\n",
      optimizer->name().c_str(), steps, scene.frames, scene.rows, scene.cols, rollout.mean_step_ms(),
      100 * rollout.max_strain(), steps ? static_cast<double>(rollout.total_iterations()) / steps : 0.0, max_iterations,
      convergence.c_str(), rollout.diverged ? rollout.divergence.c_str() : "finite", flags.out.c_str());
  // Every stored frame, each with its obstacles posed at its time (docs/design.md §14).
  if (!scene.obstacles.empty())
    std::printf("min obstacle distance = %.6g m\n", min_obstacle_distance(scene, rollout.positions));
  if (rollout.diverged) throw Error("simulate", rollout.divergence);
}

const RegisterCommand kRegister([](CLI::App& app) {
  auto flags = std::make_shared<SimulateFlags>();
  CLI::App* command = app.add_subcommand("simulate", "simulate a scene and write the rollout (HDF5, OBJ)");
  flags->scene.add_to(*command);
  add_optimizer_flags(*command, flags->optimizer);
  command->add_option("--out", flags->out, "rollout file (HDF5)")->capture_default_str();
  command->add_option("--obj-dir", flags->obj_dir, "also write every frame as DIR/frame_NNNN.obj");
  add_threads_flag(*command, flags->threads);
  command->add_flag("--warm-start", flags->warm_start, "start each step from the previous step's acceleration");
  command->callback([flags] { run_simulate(*flags); });
});

}  // namespace
}  // namespace fnopt::app
