#include "app/threads.hpp"

#include <omp.h>

namespace fnopt::app {

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

}  // namespace fnopt::app
