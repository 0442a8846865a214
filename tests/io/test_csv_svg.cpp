// The result writers shared by the studies: CSV tables (quoting, round trip, width checks) and
// SVG line charts (axes, ticks, legend, markers, points that a log axis cannot show).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <fnopt/io/csv_table.hpp>
#include <fnopt/io/svg_plot.hpp>

namespace fnopt {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  std::random_device entropy;
  return std::filesystem::temp_directory_path() / ("fnopt-test-" + std::to_string(entropy()) + "-" + name);
}

TEST(CsvTable, QuotesRoundTripsAndChecksWidths) {
  CsvTable table({"method", "N", "note"});
  table.add_row({"gd", "10", "plain"});
  table.add_row({"adam", "100", "diverged at step 3 (t = 0.05 s), \"strain\"\nnext line"});
  EXPECT_ANY_THROW(table.add_row({"too", "short"}));
  EXPECT_EQ(table.text().substr(0, 21), "method,N,note\ngd,10,p");
  EXPECT_NE(table.text().find("\"diverged at step 3 (t = 0.05 s), \"\"strain\"\"\nnext line\""), std::string::npos);
  const auto path = temp_file("table.csv");
  table.write(path.string());
  const CsvTable back = CsvTable::read(path.string());
  EXPECT_EQ(back.columns(), table.columns());
  EXPECT_EQ(back.rows(), table.rows());
  std::filesystem::remove(path);
  EXPECT_EQ(CsvTable::number(0.000123456789, 3), "0.000123");
  EXPECT_EQ(CsvTable::number(NAN), "nan");
  EXPECT_EQ(CsvTable::number(-INFINITY), "-inf");
}

TEST(SvgPlot, DrawsAxesTicksSeriesAndLegend) {
  PlotFigure figure;
  figure.title = "error & time";
  figure.notes = {"a note"};
  PlotPanel panel;
  panel.title = "e_CD vs ms/frame";
  panel.x_label = "ms/frame";
  panel.y_label = "e_CD x 10^3";
  panel.series.push_back({"gd", {{3.0, 50.0, "N=10"}, {30.0, 20.0, "N=100"}, {150.0, 8.0, "N=500", true}}});
  panel.series.push_back({"lbfgs", {{4.0, 3.0, "N=10"}, {35.0, 0.0, "N=100"}}});  // 0: not on a log axis
  panel.vertical_lines.push_back({16.0, "newton (the reference)"});
  figure.panels.push_back(panel);
  const std::string svg = render_svg(figure);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("error &amp; time"), std::string::npos);
  for (const char* text : {"ms/frame", "e_CD x 10^3", ">gd<", ">lbfgs<", "N=500", "newton (the reference)", ">1<",
                           ">10<", ">100<", "1 point not shown", "diverged"})
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '\n') > 20, true);
  std::size_t polylines = 0;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos; at = svg.find("<polyline", at + 1)) ++polylines;
  EXPECT_EQ(polylines, 2u);

  PlotFigure empty;
  empty.panels.push_back(PlotPanel{});
  EXPECT_NE(render_svg(empty).find("no data"), std::string::npos);
}

TEST(SvgPlot, ABandHasNoMarkersOrLabelsAndLongLegendEntriesDoNotOverlap) {
  PlotFigure figure;
  figure.columns = 1;
  figure.marked_meaning = "diverged in at least one motion (a long legend entry that needs room)";
  PlotPanel panel;
  panel.series.push_back({"a method with a long name", {{1, 1, "N=5", false}, {10, 0.1, "N=10", false}}});
  PlotSeries band{"frontier (fastest for its error)", {{1, 1, "", false}, {10, 0.1, "", false}}};
  band.band = true;
  panel.series.push_back(band);
  figure.panels.push_back(panel);
  const std::string svg = render_svg(figure);
  // The band: one wide translucent polyline, no marker in its colour.
  EXPECT_NE(svg.find("stroke=\"#888888\" stroke-width=\"9\" stroke-opacity=\"0.5\""), std::string::npos) << svg;
  EXPECT_EQ(svg.find("fill=\"#888888\""), std::string::npos) << svg;
  // It is drawn first (under the series it connects), and the palette's first colour stays with the method.
  EXPECT_LT(svg.find("#888888"), svg.find("#1f77b4"));
  // Legend texts on one line: each starts right of where the previous one's text ends (7.2 px per
  // character of 13 px text).
  struct Entry {
    double x, y;
    std::string text;
  };
  std::vector<Entry> entries;
  for (std::size_t at = svg.find("font-size=\"13\">"); at != std::string::npos;
       at = svg.find("font-size=\"13\">", at + 1)) {
    const std::size_t x_at = svg.rfind("<text x=\"", at) + 9, y_at = svg.find("y=\"", x_at) + 3;
    const std::size_t text_at = at + 15;
    entries.push_back({std::stod(svg.substr(x_at)), std::stod(svg.substr(y_at)),
                       svg.substr(text_at, svg.find('<', text_at) - text_at)});
  }
  ASSERT_GE(entries.size(), 3u) << svg;
  entries.erase(entries.begin(), entries.end() - 3);  // the legend comes last (before it: the axis labels)
  for (std::size_t k = 1; k < entries.size(); ++k) {
    if (entries[k].y != entries[k - 1].y) continue;
    EXPECT_GE(entries[k].x, entries[k - 1].x + 7.2 * entries[k - 1].text.size()) << entries[k].text;
  }
  EXPECT_GT(entries.back().y, entries.front().y) << "the long entries wrap onto a second line";
}

}  // namespace
}  // namespace fnopt
