#pragma once
// One row of an adjoint benchmark (`fnopt bench adjoint`, docs/design.md §15): a scene's recorded
// forward pass and the backward pass of a loss on its last frame, timed per frame, with the work
// and the memory they took.
#include <cstddef>

#include <fnopt/adjoint/recorded_rollout.hpp>
#include <fnopt/adjoint/rollout_adjoint.hpp>

namespace fnopt {

struct AdjointBenchRow {
  int rows = 0;
  int cols = 0;
  int steps = 0;
  double forward_ms_per_frame = 0.0;   // the recorded forward pass: Newton, exact steps, classification
  double backward_ms_per_frame = 0.0;  // the backward pass
  long factorizations = 0;             // the backward pass's (Cholesky, and LDL^T at saddles)
  long solves = 0;
  std::size_t record_bytes = 0;  // the states, accelerations and targets the record holds
  int saddle_steps = 0;
  int unconverged_steps = 0;
  AdjointStatus status = AdjointStatus::Exact;
};

// Records the scene's rollout and backpropagates L = |x_last - x_rest|^2 (position_loss against
// the grid's rest positions at the last frame). Throws what record_rollout and backpropagate throw.
AdjointBenchRow bench_adjoint(const ResolvedScene& scene, const RecordOptions& options = {});

}  // namespace fnopt
