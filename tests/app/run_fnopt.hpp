#pragma once
// Running the fnopt binary as a user does (FNOPT_BINARY, set by CMake for test_app), with
// passive OpenMP waiting so tests that share the cores do not spin.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/util/shell.hpp"

// `environment`: arguments of env(1) before the passive-wait setting, e.g. "OMP_NUM_THREADS=3"
// or "-u OMP_NUM_THREADS".
inline CommandResult run_fnopt(const std::string& arguments, const std::string& environment = "") {
  return run_shell("env " + environment + " OMP_WAIT_POLICY=PASSIVE " + std::string(FNOPT_BINARY) + " " + arguments);
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A CSV file's's data rows, split into fields.
inline std::vector<std::vector<std::string>> csv_rows(const std::filesystem::path& path, std::string& header) {
  std::istringstream text(read_text(path));
  std::getline(text, header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(text, line);) {
    std::vector<std::string> fields;
    std::istringstream fields_text(line);
    for (std::string field; std::getline(fields_text, field, ',');) fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}
