#include <fnopt/io/markdown_report.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

TEST(MarkdownReport, WritesHeadingsTablesImagesAndEscapesPipes) {
  MarkdownReport report("Stability");
  report.heading("Cases");
  report.paragraph("Every optimizer on every case.");
  report.table({"case", "result"}, {{"stretch x10", "finished"}, {"a|b", "diverged\nat 12"}});
  report.image("stability.svg", "strain per case");
  report.code("fnopt stability --out dir");
  EXPECT_EQ(report.text(),
            "# Stability\n\n## Cases\n\nEvery optimizer on every case.\n\n"
            "| case | result |\n| --- | --- |\n| stretch x10 | finished |\n| a\\|b | diverged at 12 |\n\n"
            "![strain per case](stability.svg)\n\n```\nfnopt stability --out dir\n```\n\n");
}

TEST(MarkdownReport, RejectsARaggedRowAndTakesACsvTable) {
  MarkdownReport report("t");
  EXPECT_THROW(report.table({"a", "b"}, {{"1"}}), Error);
  CsvTable csv({"x", "y"});
  csv.add_row({"1", "2"});
  MarkdownReport from_csv("t");
  from_csv.table(csv);
  EXPECT_NE(from_csv.text().find("| x | y |\n| --- | --- |\n| 1 | 2 |\n"), std::string::npos);
}

TEST(MarkdownReport, WriteRoundTrip) {
  const auto path = (std::filesystem::temp_directory_path() / "fnopt_report_test.md").string();
  MarkdownReport report("Round trip");
  report.bullets({"one", "two"});
  report.write(path);
  std::ifstream file(path);
  std::stringstream content;
  content << file.rdbuf();
  EXPECT_EQ(content.str(), report.text());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace fnopt
