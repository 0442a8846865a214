#pragma once
// One thread count for every method: OpenMP's (the physics, the classical solvers) and
// LibTorch's (the learned optimizer), as `--threads` sets it on the command line and
// fnopt.set_threads from Python (docs/design.md §9).
namespace fnopt {

// Sets the OpenMP and LibTorch thread counts and returns the count in effect, to be printed
// with every timing. 0 means the default: OMP_NUM_THREADS when it is set to a positive count,
// else 1 (not all cores: OpenMP threads spin while they wait, and a run beside another job on
// a 2-core machine slowed many times over with 2 threads; docs/design.md §9).
int set_thread_count(int threads);

}  // namespace fnopt
