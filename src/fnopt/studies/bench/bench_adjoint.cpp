#include <fnopt/studies/bench/bench_adjoint.hpp>

#include <algorithm>
#include <cstdio>

#include <fnopt/adjoint/adjoint_bench.hpp>
#include <fnopt/scenes/scene.hpp>
#include <fnopt/util/peak_memory.hpp>
#include <fnopt/util/progress_bar.hpp>

namespace fnopt {

// The recorded forward pass (exact Newton steps) and the backward pass of a loss on its last frame
// (adjoint/adjoint_bench.hpp), one row per resolution; peak RSS is the process's so far, so a
// row's is at least the rows' before it.
void bench_adjoint_table(const BenchRun& run) {
  const int threads = run.threads;
  std::printf(
      "adjoint of a rollout: recorded forward pass (Newton to %g m/s^2, then exact steps) and the backward pass of "
      "L = |x_last - x_rest|^2, corner handles, motion xy_v2, %d frames, dt = 1/60, %d thread%s\n",
      RecordOptions{}.acceleration_tolerance, run.frames, threads, threads == 1 ? "" : "s");
  std::printf("%6s %12s %12s %9s %10s %10s %10s %11s %9s %s\n", "res", "fwd ms/fr", "bwd ms/fr", "bwd/fwd", "factor/st",
              "solves/st", "record MB", "peak RSS MB", "saddles", "status");
  for (int n : run.resolutions) {
    Scene scene;
    scene.rows = scene.cols = n;
    scene.frames = run.frames + 1;  // --frames steps after the initial frame
    ProgressBar bar("adjoint " + std::to_string(n) + "^2", 1);
    const AdjointBenchRow row = bench_adjoint(resolve(scene));
    bar.update(1);
    bar.finish();
    const double steps = std::max(1, row.steps);
    std::printf("%4d^2 %12.1f %12.1f %9.2f %10.2f %10.2f %10.1f %11.0f %9d %s\n", n, row.forward_ms_per_frame,
                row.backward_ms_per_frame, row.backward_ms_per_frame / row.forward_ms_per_frame,
                row.factorizations / steps, row.solves / steps, row.record_bytes / 1e6, peak_resident_mb(), row.saddle_steps,
                to_string(row.status));
    std::fflush(stdout);
  }
}

}  // namespace fnopt
