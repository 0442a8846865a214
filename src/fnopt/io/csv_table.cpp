#include <fnopt/io/csv_table.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(std::move(columns)) {}

void CsvTable::add_row(std::vector<std::string> cells) {
  require(cells.size() == columns_.size(), "csv",
          "a row of " + std::to_string(cells.size()) + " cells for " + std::to_string(columns_.size()) + " columns");
  rows_.push_back(std::move(cells));
}

std::string CsvTable::quote(const std::string& cell) {
  if (cell.find_first_of(",\"\r\n") == std::string::npos) return cell;
  std::string quoted = "\"";
  for (char c : cell) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string CsvTable::number(double value, int significant) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", significant, value);
  return text;
}

CsvTable CsvTable::read(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  require(static_cast<bool>(file), path, "cannot open the file");
  const std::string content((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string cell;
  bool quoted = false, any = false;
  for (std::size_t k = 0; k < content.size(); ++k) {
    const char c = content[k];
    if (quoted) {
      if (c == '"' && k + 1 < content.size() && content[k + 1] == '"')
        cell += '"', ++k;
      else if (c == '"')
        quoted = false;
      else
        cell += c;
    } else if (c == '"') {
      quoted = true;
      any = true;
    } else if (c == ',') {
      record.push_back(cell), cell.clear();
      any = true;
    } else if (c == '\n' || c == '\r') {
      if (c == '\r' && k + 1 < content.size() && content[k + 1] == '\n') ++k;
      if (any || !cell.empty()) record.push_back(cell), records.push_back(record);
      record.clear(), cell.clear();
      any = false;
    } else {
      cell += c;
      any = true;
    }
  }
  if (any || !cell.empty()) record.push_back(cell), records.push_back(record);
  require(!records.empty(), path, "no header line");
  CsvTable table(records.front());
  for (std::size_t r = 1; r < records.size(); ++r) {
    require(records[r].size() == table.columns_.size(), path,
            "line " + std::to_string(r + 1) + " has " + std::to_string(records[r].size()) + " cells for " +
                std::to_string(table.columns_.size()) + " columns");
    table.rows_.push_back(records[r]);
  }
  return table;
}

std::string CsvTable::text() const {
  std::string out;
  auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + quote(cells[k]);
    out += "\n";
  };
  line(columns_);
  for (const auto& row : rows_) line(row);
  return out;
}

void CsvTable::write(const std::string& path) const { write_text_atomically(path, text()); }

}  // namespace fnopt
