#include <fnopt/studies/bench/bench_contact.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fnopt/contact/mesh_shape.hpp>
#include <fnopt/contact/obstacle.hpp>
#include <fnopt/methods/registry.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/simulation/rollout.hpp>
#include <fnopt/util/median.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A latitude-longitude sphere of `rings` x 2 `rings` quads (the poles' triangles), centre 0, radius 1,
// counter-clockwise seen from outside.
TriangleMesh uv_sphere(int rings) {
  TriangleMesh mesh;
  const int segments = 2 * rings;
  mesh.vertices.emplace_back(0.0, 0.0, 1.0);
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = kPi * r / rings, phi = 2.0 * kPi * s / segments;
      mesh.vertices.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  mesh.vertices.emplace_back(0.0, 0.0, -1.0);
  const int south = static_cast<int>(mesh.vertices.size()) - 1;
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.push_back({0, at(1, s), at(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      mesh.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
    mesh.triangles.push_back({at(rings - 1, s), south, at(rings - 1, s + 1)});
  }
  return mesh;
}

// One row of the table: a scene without and with what is timed; whether the two rollouts must be
// the same (a barrier out of range adds exact zeros).
struct ContactCase {
  std::string name;
  Scene without, with;
  bool same_expected;
};

// The cases at an n x n grid (docs/design.md §14):
//  * far-obstacles: the benchmark scene, and with a floor 4 m below and a sphere 3 m behind;
//  * far-mesh: the same with a sphere of 1,520 triangles where the analytic sphere was;
//  * self-contact: the sphere drape (examples/scenes/drape.scene: the cloth let go of flat above a
//    sphere and a floor) with self-contact off and on.
// Self-contact stays off in the far cases, so that they time the obstacles alone.
std::vector<ContactCase> contact_cases(int n, int frames) {
  Scene benchmark;
  benchmark.rows = benchmark.cols = n;
  benchmark.frames = frames;
  benchmark.self_contact = AutoSwitch::Off;
  Scene far = benchmark;
  apply_scene_setting(far, "obstacle", "plane point=0,0,-5 normal=0,0,1;sphere center=0.5,3,-0.5 radius=0.2");
  Scene far_mesh = benchmark;
  static const auto sphere = std::make_shared<const MeshShape>(MeshShape::single(uv_sphere(20), 0.2, Vec3(0.5, 3, -0.5)));
  far_mesh.obstacles.push_back(Obstacle::mesh(sphere, "a generated sphere of 1,520 triangles"));
  Scene drape = benchmark;
  drape.handles = "none";
  drape.placement = Placement::Horizontal;
  apply_scene_setting(drape, "obstacle",
                      "sphere center=0,0,-0.3 radius=0.25 friction=0.3;plane point=0,0,-0.6 normal=0,0,1 friction=0.3");
  Scene drape_self = drape;
  drape_self.self_contact = AutoSwitch::On;
  return {{"far-obstacles", benchmark, far, true},
          {"far-mesh", benchmark, far_mesh, true},
          {"self-contact", drape, drape_self, false}};
}

}  // namespace

// Each case in --repeat rounds per resolution and method, the order alternating; medians, their
// ratio, and for the far cases whether the two rollouts are the same (they must be).
void bench_contact_table(const BenchRun& run) {
  const int threads = run.threads;
  std::printf(
      "contact's cost: %d frames, dt = 1/60, %d thread%s, medians of %d alternated runs. far-obstacles: the benchmark "
      "scene (corner handles, xy_v2) without and with a floor z = -5 m and a sphere centre (0.5, 3, -0.5) m radius "
      "0.2 m; far-mesh: the same sphere as 1,520 triangles; self-contact: the sphere drape (released cloth, sphere "
      "and floor) without and with self-contact\n",
      run.frames, threads, threads == 1 ? "" : "s", run.repeat);
  std::printf("%6s %8s %14s %16s %16s %8s %s\n", "res", "method", "case", "without ms/frame", "with ms/frame", "ratio",
              "same rollout");
  for (int n : run.resolutions)
    for (const ContactCase& c : contact_cases(n, run.frames))
      for (const std::string method : {"pqn", "newton"}) {
        OptimizerChoice choice;
        choice.name = method;
        RolloutOptions options;
        options.solve = choice.solve_options();
        const ResolvedScene without = resolve(c.without), with = resolve(c.with);
        std::vector<double> without_ms, with_ms;
        bool same = true;
        ProgressBar bar("contact " + std::to_string(n) + "^2 " + c.name + " " + method, 2 * run.repeat);
        for (int round = 0; round < run.repeat; ++round) {
          // The order alternates between rounds (ABBA...), so that neither run always goes second.
          const auto without_optimizer = choice.make(), with_optimizer = choice.make();
          RolloutResult without_run, with_run;
          if (round % 2 == 0) without_run = run_rollout(without, *without_optimizer, options);
          with_run = run_rollout(with, *with_optimizer, options);
          bar.update(2 * round + 1);
          if (round % 2 == 1) without_run = run_rollout(without, *without_optimizer, options);
          bar.update(2 * round + 2);
          without_ms.push_back(without_run.mean_step_ms());
          with_ms.push_back(with_run.mean_step_ms());
          same = same && without_run.positions == with_run.positions;
        }
        bar.finish();
        const double without_median = median(without_ms), with_median = median(with_ms);
        std::printf("%4d^2 %8s %14s %16.2f %16.2f %8.3f %s\n", n, method.c_str(), c.name.c_str(), without_median,
                    with_median, with_median / without_median, c.same_expected ? (same ? "yes" : "no") : "-");
        std::fflush(stdout);
      }
}

}  // namespace fnopt
