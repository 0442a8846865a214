#pragma once
// A rollout's adjoint (fnopt bench adjoint): the recorded forward pass (exact Newton steps) and the
// backward pass of a loss on its last frame (adjoint/adjoint_bench.hpp), one row per resolution
// with the process's peak resident memory so far.
#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

void bench_adjoint_table(const BenchRun& run);

}  // namespace fnopt
