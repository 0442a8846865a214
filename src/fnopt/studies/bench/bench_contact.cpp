#include <fnopt/studies/bench/bench_contact.hpp>

#include <cstdio>

#include <fnopt/methods/registry.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/median.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {

// The contact term's cost where the cloth never comes near an obstacle (docs/design.md §14): the
// benchmark scene with and without two far obstacles (a floor 4 m below, a sphere 3 m behind), in
// --repeat rounds per resolution and method, the order alternating; medians, their ratio, and whether the
// two rollouts are the same (they must be: a barrier out of range adds exact zeros).
void bench_contact_table(const BenchRun& run) {
  const int threads = run.threads;
  std::printf(
      "contact with far obstacles: corner handles, motion xy_v2, %d frames, dt = 1/60, %d thread%s, medians of %d "
      "alternated runs; the obstacles: floor z = -5 m, sphere centre (0.5, 3, -0.5) m radius 0.2 m\n",
      run.frames, threads, threads == 1 ? "" : "s", run.repeat);
  std::printf("%6s %8s %14s %14s %8s %s\n", "res", "method", "free ms/frame", "far ms/frame", "ratio", "same rollout");
  for (int n : run.resolutions)
    for (const std::string method : {"pqn", "newton"}) {
      Scene free_scene;
      free_scene.rows = free_scene.cols = n;
      free_scene.frames = run.frames;
      Scene far_scene = free_scene;
      apply_scene_setting(far_scene, "obstacle",
                          "plane point=0,0,-5 normal=0,0,1;sphere center=0.5,3,-0.5 radius=0.2");
      OptimizerChoice choice;
      choice.name = method;
      RolloutOptions options;
      options.solve = choice.solve_options();
      std::vector<double> free_ms, far_ms;
      bool same = true;
      ProgressBar bar("contact " + std::to_string(n) + "^2 " + method, 2 * run.repeat);
      for (int round = 0; round < run.repeat; ++round) {
        // The order alternates between rounds (ABBA...), so that neither run always goes second.
        const auto free_optimizer = choice.make(), far_optimizer = choice.make();
        RolloutResult free_run, far_run;
        if (round % 2 == 0) free_run = run_rollout(resolve(free_scene), *free_optimizer, options);
        far_run = run_rollout(resolve(far_scene), *far_optimizer, options);
        bar.update(2 * round + 1);
        if (round % 2 == 1) free_run = run_rollout(resolve(free_scene), *free_optimizer, options);
        bar.update(2 * round + 2);
        free_ms.push_back(free_run.mean_step_ms());
        far_ms.push_back(far_run.mean_step_ms());
        same = same && free_run.positions == far_run.positions;
      }
      bar.finish();
      const double free_median = median(free_ms), far_median = median(far_ms);
      std::printf("%4d^2 %8s %14.2f %14.2f %8.3f %s\n", n, method.c_str(), free_median, far_median,
                  far_median / free_median, same ? "yes" : "no");
      std::fflush(stdout);
    }
}

}  // namespace fnopt
