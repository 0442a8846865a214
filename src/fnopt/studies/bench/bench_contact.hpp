#pragma once
// Contact's cost (fnopt bench contact, docs/design.md §14), pqn and newton: far analytic obstacles
// and a far mesh on the benchmark scene (where the cloth never comes near them), and self-contact
// on the sphere drape.
#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

void bench_contact_table(const BenchRun& run);

}  // namespace fnopt
