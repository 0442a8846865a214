#include "app/threads.hpp"

#include <ATen/Parallel.h>
#include <omp.h>

#include <cstdlib>

namespace fnopt::app {
namespace {

// Asked for explicitly because LibTorch, once initialised (a model loaded), sets OpenMP's
// thread count to its own default, which is 1 with Debian's libtorch: leaving the defaults
// alone ran the learned optimizer on one core.
int all_cores_thread_count() {
  // OMP_NUM_THREADS may be a list ("4,2"); its first entry is the outer level's count.
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const long count = std::strtol(env, nullptr, 10);
    if (count > 0) return static_cast<int>(count);
  }
  return omp_get_num_procs();
}

}  // namespace

CLI::Option* add_threads_flag(CLI::App& command, int& threads, const std::string& help) {
  const int most = 4 * omp_get_num_procs();
  return command.add_option("--threads", threads, help)
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
  const int count = threads > 0 ? threads : all_cores_thread_count();
  omp_set_num_threads(count);
  at::set_num_threads(count);
  return count;
}

}  // namespace fnopt::app
