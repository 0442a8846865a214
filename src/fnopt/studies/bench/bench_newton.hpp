#pragma once
// The Newton reference's cost (fnopt bench newton): ms/frame, iterations, builds of its
// preconditioner, CG iterations and the worst step, per resolution; with repeat > 1 each
// resolution is timed in rounds (a slow phase of the machine touches every resolution alike) and
// the row gives medians and ms/frame's range.
#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

void bench_newton_table(const BenchRun& run);

}  // namespace fnopt
