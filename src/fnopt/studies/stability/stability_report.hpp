#pragma once
// `fnopt stability`'s report.md and stability.svg (docs/design.md §8 "Stability"): the setup,
// the cases with their grid-unit stiffnesses, what fails where, and the table of every row.
#include <string>
#include <vector>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/studies/stability/stability_study.hpp>

namespace fnopt {

struct StabilityReportFiles {
  std::string svg, report;  // paths
  std::string started;      // "2026-01-02 13:45", when the study started
};

// `rows`: the measured rows of this plan; `table`: stability.csv as written. `complete`: false
// marks the report partial (the study is still running or was stopped).
void write_stability_report(const StabilityStudy& study, const StabilityReportFiles& files,
                            const std::vector<StabilityRow>& rows, const CsvTable& table, bool complete);

}  // namespace fnopt
