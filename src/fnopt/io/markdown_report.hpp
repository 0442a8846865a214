#pragma once
// A study's report: one Markdown file that a person reads without running anything,
// next to the study's CSV tables and SVG plots in the same folder. Tables are GitHub-flavoured
// Markdown; '|' in a cell is escaped so a cell never splits a row.
#include <string>
#include <vector>

#include <fnopt/io/csv_table.hpp>

namespace fnopt {

class MarkdownReport {
 public:
  explicit MarkdownReport(const std::string& title);

  // "## text" (level 2) ... "###### text"; level is clamped to 2..6.
  void heading(const std::string& text, int level = 2);
  // A paragraph; embedded newlines are kept.
  void paragraph(const std::string& text);
  // One "- item" line per entry.
  void bullets(const std::vector<std::string>& items);
  // A table; throws Error if a row does not have one cell per header column.
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // The whole CSV table (every column), e.g. a study's result file.
  void table(const CsvTable& csv);
  // An image (SVG/PNG) by its path relative to the report, with its caption as alt text.
  void image(const std::string& relative_path, const std::string& caption);
  // A fenced code block (the command that produced the study, say).
  void code(const std::string& text);

  const std::string& text() const { return text_; }
  // Writes text() atomically.
  void write(const std::string& path) const;

 private:
  std::string text_;
};

}  // namespace fnopt
