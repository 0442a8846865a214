#include <fnopt/adjoint/adjoint_bench.hpp>

#include <fnopt/adjoint/rollout_loss.hpp>

namespace fnopt {

AdjointBenchRow bench_adjoint(const ResolvedScene& scene, const RecordOptions& options) {
  const RecordedRollout rollout = record_rollout(scene, options);
  const RolloutLoss loss = position_loss(rollout, {{rollout.frame_count() - 1, scene.grid.rest_positions()}});
  const RolloutGradient gradient = backpropagate(rollout, loss.gradient);
  AdjointBenchRow row;
  row.rows = scene.grid.rows;
  row.cols = scene.grid.cols;
  row.steps = rollout.step_count();
  row.forward_ms_per_frame = rollout.forward_ms / row.steps;
  row.backward_ms_per_frame = gradient.backward_ms / row.steps;
  row.factorizations = gradient.factorizations;
  row.solves = gradient.solves;
  row.record_bytes = rollout.memory_bytes();
  row.saddle_steps = static_cast<int>(gradient.saddle_steps.size());
  row.unconverged_steps = static_cast<int>(gradient.unconverged_steps.size());
  row.status = gradient.status;
  return row;
}

}  // namespace fnopt
