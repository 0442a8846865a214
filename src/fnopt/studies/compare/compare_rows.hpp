#pragma once
// compare.csv's rows: its columns, a run's row, a row back into a run (--resume), and a run's
// result as text for the trip from the rank that ran it to rank 0 (studies/sweep/sweep_runner.hpp).
#include <string>
#include <vector>

#include <fnopt/studies/compare/compare_report.hpp>

namespace fnopt {

const std::vector<std::string>& compare_columns();
// The columns that name a run (ResumedRows): method, N, resolution, motion.
const std::vector<std::string>& compare_key_columns();
std::vector<std::string> compare_csv_row(const RunResult& result, int threads);
// A row of an earlier compare.csv back into a result (--resume).
RunResult run_result_of_row(const RunSpec& spec, const std::vector<std::string>& row);

// Every field at full precision: the frontier is marked on the values, not the CSV's rounded
// text, so that rank 0 writes what one process would.
std::string encode_run_result(const RunResult& result);
// Throws Error("compare", ...) on a damaged text.
RunResult decode_run_result(const std::string& text);

}  // namespace fnopt
