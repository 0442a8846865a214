// Closed-loop control from C++ with fnopt::core alone: each step the two corner handles are
// moved by a function of the cloth's state (here: lifted until the cloth's lowest point is
// 10 cm above where it started), then the step is solved by pqn.
#include <fnopt/fnopt.hpp>
#include <fnopt/scenes/scene_settings.hpp>

#include <algorithm>
#include <cstdio>
#include <vector>

int main() try {
  const fnopt::Scene scene = fnopt::apply_scene_settings({}, {{"res", "16"}, {"motion", "static"}});
  const fnopt::ResolvedScene resolved = fnopt::resolve(scene);
  fnopt::PqnOptimizer pqn;
  fnopt::RolloutOptions options;
  options.solve.max_iterations = 10;
  fnopt::Simulator simulator(resolved, pqn, options);

  auto lowest = [&] {
    double z = simulator.positions()[2];
    for (int k = 0; k < resolved.grid.vertex_count(); ++k) z = std::min(z, simulator.positions()[3 * k + 2]);
    return z;
  };
  const double goal = lowest() + 0.10;
  for (int step = 1; step <= 120; ++step) {
    std::vector<fnopt::Vec3> handles;
    for (int v : simulator.handle_vertices()) handles.push_back(fnopt::vertex(simulator.positions(), v));
    if (lowest() < goal)
      for (auto& p : handles) p.z() += 0.002;  // 12 cm/s upwards
    const fnopt::StepRecord record = simulator.step(handles);
    if (step % 30 == 0)
      std::printf("t = %.2f s: lowest point %+.3f m (goal %+.3f), %d iterations, max strain %.2f %%\n",
                  simulator.time(), lowest(), goal, record.iterations, 100 * record.max_strain);
  }
  return 0;
} catch (const fnopt::Error& e) {
  std::fprintf(stderr, "closed_loop: %s\n", e.what());
  return 2;
}
