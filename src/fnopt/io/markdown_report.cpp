#include <fnopt/io/markdown_report.hpp>

#include <algorithm>

#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

std::string cell_text(const std::string& cell) {
  std::string out;
  for (char c : cell) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string table_row(const std::vector<std::string>& cells) {
  std::string line = "|";
  for (const auto& cell : cells) line += " " + cell_text(cell) + " |";
  return line + "\n";
}

}  // namespace

MarkdownReport::MarkdownReport(const std::string& title) : text_("# " + title + "\n\n") {}

void MarkdownReport::heading(const std::string& text, int level) {
  text_ += std::string(static_cast<std::size_t>(std::clamp(level, 2, 6)), '#') + " " + text + "\n\n";
}

void MarkdownReport::paragraph(const std::string& text) { text_ += text + "\n\n"; }

void MarkdownReport::bullets(const std::vector<std::string>& items) {
  for (const auto& item : items) text_ += "- " + item + "\n";
  text_ += "\n";
}

void MarkdownReport::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  text_ += table_row(header);
  text_ += table_row(std::vector<std::string>(header.size(), "---"));
  for (const auto& row : rows) {
    if (row.size() != header.size())
      throw Error("report table: a row has " + std::to_string(row.size()) + " cells, the header " +
                  std::to_string(header.size()));
    text_ += table_row(row);
  }
  text_ += "\n";
}

void MarkdownReport::table(const CsvTable& csv) { table(csv.columns(), csv.rows()); }

void MarkdownReport::image(const std::string& relative_path, const std::string& caption) {
  text_ += "![" + cell_text(caption) + "](" + relative_path + ")\n\n";
}

void MarkdownReport::code(const std::string& text) { text_ += "```\n" + text + "\n```\n\n"; }

void MarkdownReport::write(const std::string& path) const { write_text_atomically(path, text_); }

}  // namespace fnopt
