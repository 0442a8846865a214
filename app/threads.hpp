#pragma once
#include <CLI/CLI.hpp>

#include <fnopt/methods/thread_count.hpp>  // set_thread_count

namespace fnopt::app {

// --threads, the same for every subcommand: a count from 1 to 4 per core (more only
// oversubscribes); `threads` keeps 0 (the default of fnopt::set_thread_count) unless it is given.
CLI::Option* add_threads_flag(CLI::App& command, int& threads);

}  // namespace fnopt::app
