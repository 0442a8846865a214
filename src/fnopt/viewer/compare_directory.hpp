#pragma once
// A `fnopt compare` output directory as the viewer shows it (docs/design.md §11): the rows of
// compare.csv and, for the runs whose rollouts were kept (--keep-rollouts), that rollout file and
// the Newton reference of its scene, the only files of the directory the viewer serves.
#include <string>
#include <vector>

namespace fnopt {

struct CompareRun {
  std::vector<std::string> cells;  // the row of compare.csv
  std::string rollout;             // DIR/rollout_<method>[_<N>]_<res>_<motion>.h5, "" if not kept
  std::string reference;           // DIR/newton_reference_<res>_<motion>_<hash>.h5, "" if none
};

struct CompareDirectory {
  std::string path;
  std::vector<std::string> columns;
  std::vector<CompareRun> runs;
};

// Throws Error naming the directory if it has no compare.csv or the table lacks a column the
// chart needs (method, N, resolution, motion, ms_per_frame, e_cd_x1e3, frontier).
CompareDirectory read_compare_directory(const std::string& path);

// {"directory", "columns", "rows": [{"cells": [...], "rollout": name or null, "reference": ...}]}
std::string compare_directory_json(const CompareDirectory& directory);

}  // namespace fnopt
