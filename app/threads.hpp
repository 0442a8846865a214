#pragma once
namespace fnopt::app {

// Sets the OpenMP and LibTorch thread counts and returns the count in effect, to be printed
// with every timing. 0 means all cores: OMP_NUM_THREADS when it is set to a positive count,
// else every processor this process may run on.
int set_thread_count(int threads);

}  // namespace fnopt::app
