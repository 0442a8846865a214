#pragma once
#include <CLI/CLI.hpp>

namespace fnopt::app {

// --threads, the same for every subcommand: a count from 1 to 4 per core (more only
// oversubscribes); `threads` keeps 0 (the default, see set_thread_count) unless it is given.
CLI::Option* add_threads_flag(CLI::App& command, int& threads);

// Sets the OpenMP and LibTorch thread counts and returns the count in effect, to be printed
// with every timing. 0 means the default, the same for every subcommand: OMP_NUM_THREADS when
// it is set to a positive count, else 1.
int set_thread_count(int threads);

}  // namespace fnopt::app
