#include <fnopt/methods/thread_count.hpp>

#include <ATen/Parallel.h>
#include <omp.h>

#include <cstdlib>

namespace fnopt {
namespace {

// OMP_NUM_THREADS where it is set, else one thread. OMP_WAIT_POLICY is read once when the
// runtime loads, so the count is set explicitly; LibTorch, once initialised, resets OpenMP's.
int default_thread_count() {
  // OMP_NUM_THREADS may be a list ("4,2"); its first entry is the outer level's count.
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const long count = std::strtol(env, nullptr, 10);
    if (count > 0) return static_cast<int>(count);
  }
  return 1;
}

}  // namespace

int set_thread_count(int threads) {
  const int count = threads > 0 ? threads : default_thread_count();
  omp_set_num_threads(count);
  at::set_num_threads(count);
  return count;
}

}  // namespace fnopt
