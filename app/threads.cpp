#include "app/threads.hpp"

#include <ATen/Parallel.h>
#include <omp.h>

#include <cstdlib>

namespace fnopt::app {
namespace {

// The default when --threads is not given: OMP_NUM_THREADS where it is set, else one thread.
// Not all cores: OpenMP threads spin while they wait (OMP_WAIT_POLICY, read once when the
// runtime loads, so the program cannot change it), and with one other job on a 2-core machine
// a 2-thread run of an 8x8 grid took 1344 ms/frame against 14.5 with one thread
// (docs/design.md §9). Set explicitly because LibTorch, once initialised, resets OpenMP's count.
int default_thread_count() {
  // OMP_NUM_THREADS may be a list ("4,2"); its first entry is the outer level's count.
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const long count = std::strtol(env, nullptr, 10);
    if (count > 0) return static_cast<int>(count);
  }
  return 1;
}

}  // namespace

CLI::Option* add_threads_flag(CLI::App& command, int& threads) {
  const int most = 4 * omp_get_num_procs();
  return command
      .add_option("--threads", threads,
                  "threads (default: $OMP_NUM_THREADS, else 1; more pay on an otherwise idle machine only)")
      ->check(CLI::Validator(
          [most](std::string& text) -> std::string {
            int value = 0;
            try {
              std::size_t used = 0;
              value = std::stoi(text, &used);
              if (used != text.size()) return "expected a whole number of threads, got '" + text + "'";
            } catch (const std::exception&) {
              return "expected a whole number of threads, got '" + text + "'";
            }
            if (value < 1 || value > most)
              return "must lie in [1, " + std::to_string(most) + "] on this machine (4 per core), got " + text;
            return "";
          },
          "1.." + std::to_string(most)));
}

int set_thread_count(int threads) {
  const int count = threads > 0 ? threads : default_thread_count();
  omp_set_num_threads(count);
  at::set_num_threads(count);
  return count;
}

}  // namespace fnopt::app
