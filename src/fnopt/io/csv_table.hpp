#pragma once
// A small CSV table (RFC 4180 quoting) for result files: fixed columns, rows of text cells,
// written atomically so that a reader never sees half a file, and rewritable after every row
// so that a long study leaves its finished rows on disk if it is stopped.
#include <string>
#include <vector>

namespace fnopt {

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns);

  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<std::vector<std::string>>& rows() const { return rows_; }

  // Throws Error if the row does not have one cell per column.
  void add_row(std::vector<std::string> cells);
  // The whole table, header first, "\n" line ends.
  std::string text() const;
  // Writes text() to `path` (temporary name, then rename).
  void write(const std::string& path) const;

  // Reads a file written by write() (or any RFC 4180 CSV whose first line is the header).
  // Throws Error naming the file if it cannot be read or a row has the wrong width.
  static CsvTable read(const std::string& path);

  // A number with `significant` digits in the shortest general form; "nan", "inf", "-inf".
  static std::string number(double value, int significant = 6);
  // A cell quoted if it holds a comma, quote, CR or LF.
  static std::string quote(const std::string& cell);

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace fnopt
