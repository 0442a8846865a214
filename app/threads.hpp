#pragma once
namespace fnopt::app {

// The thread count of "all cores": OMP_NUM_THREADS when it is set to a positive count, else
// every processor this process may run on. Asked for explicitly because LibTorch, once
// initialised (a model loaded), sets OpenMP's thread count to its own default, which is 1 with
// Debian's libtorch: leaving the defaults alone ran the learned optimizer on one core.
int all_cores_thread_count();

// Sets the OpenMP and LibTorch thread counts (0: all cores) and returns the count in effect,
// to be printed with every timing.
int set_thread_count(int threads);

}  // namespace fnopt::app
