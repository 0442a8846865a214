#pragma once
namespace fnopt::app {

// Sets the OpenMP and LibTorch thread counts (0: leave the defaults) and returns the count in
// effect, to be printed with every timing.
int set_thread_count(int threads);

}  // namespace fnopt::app
