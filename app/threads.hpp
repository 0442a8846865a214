#pragma once
#include <CLI/CLI.hpp>

namespace fnopt::app {

// --threads, validated the same way by every subcommand: a count from 1 to 4 per core (more
// only oversubscribes). `help` says what the default is.
CLI::Option* add_threads_flag(CLI::App& command, int& threads, const std::string& help);

// Sets the OpenMP and LibTorch thread counts and returns the count in effect, to be printed
// with every timing. 0 means all cores: OMP_NUM_THREADS when it is set to a positive count,
// else every processor this process may run on.
int set_thread_count(int threads);

}  // namespace fnopt::app
