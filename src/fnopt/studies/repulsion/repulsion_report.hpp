#pragma once
// `fnopt repulsion-study`'s tables and report (docs/design.md §8 "Self-contact"): the columns of
// repulsion.csv and repulsion_energy.csv, and, at the end, repulsion.svg (energy over time),
// report.md and the table on stdout.
#include <string>
#include <vector>

#include <fnopt/studies/repulsion/repulsion_study.hpp>

namespace fnopt {

// repulsion.csv: one row per run.
const std::vector<std::string>& repulsion_run_columns();
// repulsion_energy.csv: the repulsive energy of every frame of every run.
const std::vector<std::string>& repulsion_energy_columns();

// `runs`: the rows of this plan's runs, in plan order; `energy`: repulsion_energy.csv's rows.
void write_repulsion_report(const RepulsionStudy& study, const std::vector<std::vector<std::string>>& runs,
                            const std::vector<std::vector<std::string>>& energy);

}  // namespace fnopt
