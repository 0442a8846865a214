#pragma once
// The contact term's cost where the cloth never comes near an obstacle (fnopt bench contact,
// docs/design.md §14): the benchmark scene with and without two far obstacles, pqn and newton.
#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

void bench_contact_table(const BenchRun& run);

}  // namespace fnopt
