#include <fnopt/studies/sweep/resumed_rows.hpp>

#include <algorithm>
#include <filesystem>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

ResumedRows::ResumedRows(const std::string& path, const std::vector<std::string>& columns,
                         const std::vector<std::string>& key_columns, bool resume, const std::string& study) {
  if (!resume || !std::filesystem::exists(path)) return;
  const CsvTable earlier = CsvTable::read(path);
  require(earlier.columns() == columns, path, "written by another version of " + study + ": cannot resume");
  std::vector<std::size_t> at;
  for (const auto& name : key_columns)
    at.push_back(static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin()));
  for (const Row& row : earlier.rows()) {
    std::vector<std::string> values;
    for (std::size_t k : at) values.push_back(row.at(k));
    keys_.push_back(key(values));
    index_[keys_.back()] = rows_.size();
    rows_.push_back(row);
  }
}

std::string ResumedRows::key(const std::vector<std::string>& values) {
  std::string text;
  for (const auto& value : values) text += (text.empty() ? "" : "|") + value;
  return text;
}

const ResumedRows::Row* ResumedRows::find(const std::string& key) const {
  const auto found = index_.find(key);
  return found == index_.end() ? nullptr : &rows_[found->second];
}

std::vector<ResumedRows::Row> ResumedRows::unplanned(const std::set<std::string>& planned) const {
  std::vector<Row> rows;
  for (std::size_t k = 0; k < rows_.size(); ++k)
    if (!planned.count(keys_[k]) && index_.at(keys_[k]) == k) rows.push_back(rows_[k]);
  return rows;
}

}  // namespace fnopt
