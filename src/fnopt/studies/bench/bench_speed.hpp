#pragma once
// One table of what each method costs (fnopt bench speed, docs/design.md §9): pqn 10, fnopt 10
// and the Newton reference on the benchmark scene at each resolution, with 1 and 2 threads, each
// run in a process of its own (this executable, `bench speed --row`), so that its peak resident
// memory is its own; beside fnopt 1.0's figures (speed-1.0.csv, installed with the models).
#include <string>
#include <vector>

#include <fnopt/studies/bench/bench_run.hpp>

namespace fnopt {

// One timed rollout's figures.
struct SpeedMeasurement {
  double ms_per_frame = 0.0;           // ms_per_frame() of the rollout (median over --repeat runs)
  double evaluations_per_frame = 0.0;  // the step objective's evaluations (StepRecord::evaluations)
  double gradients_per_frame = 0.0;    // those with a gradient
  double peak_mb = 0.0;                // the process's peak resident memory [MB]
  int converged = 0, steps = 0;
};

// A method of the table and its budget ("pqn:10", "newton"): the benchmark scene (corner handles,
// xy_v2) at run.resolutions[0] with the thread count in effect, run.repeat times, in this process.
// Throws Error("row", ...) for a malformed row, Error("optimizer", ...) for an unknown method.
SpeedMeasurement measure_speed(const BenchRun& run, const std::string& row);

// The line a row's process prints, and its parse (false if `line` is not one).
std::string speed_line(const SpeedMeasurement& m);
bool parse_speed_line(const std::string& line, SpeedMeasurement& m);

// fnopt 1.0's ms/frame for (resolution, threads, method and budget as "pqn 10"), from a CSV whose
// first columns are res,threads,method,ms_per_frame (then where each figure comes from). Throws
// Error("baseline", ...) naming the file and line for a malformed row, what CsvTable::read throws
// for a file it cannot read.
struct SpeedBaseline {
  int res = 0, threads = 0;
  std::string method;
  double ms_per_frame = 0.0;
};
std::vector<SpeedBaseline> read_speed_baseline(const std::string& path);

// With run.row set: measure_speed's line. Otherwise the table: every resolution, method and thread
// count, each in a child process of this executable. Throws Error("bench", ...)
// where a row's process fails, with its last line.
void bench_speed_table(const BenchRun& run);

}  // namespace fnopt
