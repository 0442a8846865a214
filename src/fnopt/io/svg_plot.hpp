#pragma once
// Line charts as standalone SVG (no dependencies), readable without the data file: a title and
// notes, a grid of panels with labelled axes and ticks (linear or log), one polyline per series
// through its points in the given order, point labels, vertical reference lines, and one legend
// for the figure (a series keeps its colour in every panel). On a log axis, points that are not
// positive cannot be drawn: they are left out and the panel says how many.
#include <string>
#include <vector>

namespace fnopt {

struct PlotPoint {
  double x = 0.0, y = 0.0;
  std::string label;    // drawn next to the point (e.g. the iteration budget), may be empty
  bool marked = false;  // drawn as a crossed hollow marker (e.g. a diverged run)
};

struct PlotSeries {
  std::string name;
  std::vector<PlotPoint> points;
  // Drawn as a wide translucent grey band under the other series, without markers or labels
  // (e.g. a frontier through points that other series already mark).
  bool band = false;
};

struct PlotVerticalLine {
  double x = 0.0;
  std::string label;
};

struct PlotPanel {
  std::string title, x_label, y_label;
  bool log_x = true, log_y = true;
  std::vector<PlotSeries> series;
  std::vector<PlotVerticalLine> vertical_lines;  // dashed, labelled
};

struct PlotFigure {
  std::string title;
  std::vector<std::string> notes;           // lines of text under the title
  int columns = 2;                          // panels per row
  std::string marked_meaning = "diverged";  // legend entry for marked points ("" = none)
  std::vector<PlotPanel> panels;
};

std::string render_svg(const PlotFigure& figure);
// Writes render_svg(figure) atomically.
void write_svg(const std::string& path, const PlotFigure& figure);

}  // namespace fnopt
