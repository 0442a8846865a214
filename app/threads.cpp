#include "app/threads.hpp"

#include <ATen/Parallel.h>
#include <omp.h>

namespace fnopt::app {

int set_thread_count(int threads) {
  if (threads > 0) {
    omp_set_num_threads(threads);
    at::set_num_threads(threads);
  }
  return omp_get_max_threads();
}

}  // namespace fnopt::app
