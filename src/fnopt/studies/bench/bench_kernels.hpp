#pragma once
// The angle springs' gradient throughput (fnopt bench kernels, docs/design.md §9): stencils per
// second of the shear and bend terms' accumulate_gradient at each resolution, on the scalar kernel
// and on every SIMD level this CPU has (cloth/angle_term.hpp), on a deformed cloth.
#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

void bench_kernels_table(const BenchRun& run);

}  // namespace fnopt
