#pragma once
// stability.csv's rows: its columns, a row's cells, and a row back from them (--resume).
#include <string>
#include <vector>

#include <fnopt/studies/stability/stability_run.hpp>

namespace fnopt {

// The CSV columns of DIR/stability.csv, one row per case x method.
const std::vector<std::string>& stability_columns();
std::vector<std::string> stability_csv_row(const StabilityRow& row);
// A row of an earlier stability.csv back into a result (--resume). Throws Error on a wrong width.
StabilityRow stability_row_from_csv(const std::vector<std::string>& cells);
// A cell of a row: the value to `digits` significant digits, empty if it is undefined (NaN).
std::string stability_cell(double value, int digits = 4);
// "N=100", "tol 1e-09 (max 1000)"
std::string budget_text(const InnerSolveOptions& solve);

}  // namespace fnopt
