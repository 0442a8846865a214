#include <fnopt/io/svg_plot.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <fnopt/util/atomic_file.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

constexpr double kPanelWidth = 540, kPanelHeight = 400;
constexpr double kLeft = 78, kRight = 24, kTop = 44, kBottom = 58;
constexpr double kBandWidth = 9;          // px, a band series' stroke
constexpr double kLegendCharWidth = 7.2;  // px per character of 13 px Helvetica, for the legend's layout
const char* const kBandColour = "#888888";
const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

std::string escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string fmt(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", v);
  return text;
}

std::string tick_text(double v) {
  char text[32];
  if (v != 0.0 && (std::abs(v) >= 1e5 || std::abs(v) < 1e-3))
    std::snprintf(text, sizeof text, "%.0e", v);
  else
    std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// One axis: the data range mapped to pixels, with its ticks.
struct Axis {
  bool log = true;
  double lo = 0.0, hi = 1.0;  // in axis units (log10 for a log axis)
  std::vector<double> ticks;  // data values

  void fit(double min_value, double max_value) {
    if (log) {
      lo = std::floor(std::log10(min_value));
      hi = std::ceil(std::log10(max_value));
      if (hi - lo < 1) hi = lo + 1;
      const bool fine = hi - lo <= 2;
      for (int e = static_cast<int>(lo); e <= static_cast<int>(hi); ++e)
        for (double m : {1.0, 2.0, 5.0})
          if (m == 1.0 || fine) {
            const double v = m * std::pow(10.0, e);
            if (std::log10(v) <= hi + 1e-9) ticks.push_back(v);
          }
    } else {
      if (min_value == max_value) {
        min_value -= 0.5 * std::max(1.0, std::abs(min_value));
        max_value += 0.5 * std::max(1.0, std::abs(max_value));
      }
      const double raw = (max_value - min_value) / 6;
      const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
      double step = magnitude;
      for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * magnitude >= raw) {
          step = m * magnitude;
          break;
        }
      lo = std::floor(min_value / step) * step;
      hi = std::ceil(max_value / step) * step;
      for (double v = lo; v <= hi + 0.5 * step; v += step) ticks.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
    }
  }
  double unit(double v) const { return log ? std::log10(v) : v; }
  double fraction(double v) const { return (unit(v) - lo) / (hi - lo); }
};

bool drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); }

// A panel's plotting area in pixels and its two axes.
struct PanelFrame {
  double x0, x1, y0, y1;
  Axis ax, ay;
  double px(double v) const { return x0 + ax.fraction(v) * (x1 - x0); }
  double py(double v) const { return y1 - ay.fraction(v) * (y1 - y0); }
};

// Grid lines, tick labels and the axis titles.
void render_axes(std::ostringstream& svg, const PlotPanel& panel, const PanelFrame& f, double ox) {
  for (double t : f.ax.ticks) {
    const double x = f.px(t);
    svg << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(f.y0) << "\" x2=\"" << fmt(x) << "\" y2=\"" << fmt(f.y1)
        << "\" stroke=\"#e4e4e4\"/>\n<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(f.y1) << "\" x2=\"" << fmt(x)
        << "\" y2=\"" << fmt(f.y1 + 5) << "\" stroke=\"#333\"/>\n<text x=\"" << fmt(x) << "\" y=\"" << fmt(f.y1 + 19)
        << "\" text-anchor=\"middle\" font-size=\"12\">" << tick_text(t) << "</text>\n";
  }
  for (double t : f.ay.ticks) {
    const double y = f.py(t);
    svg << "<line x1=\"" << fmt(f.x0) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(f.x1) << "\" y2=\"" << fmt(y)
        << "\" stroke=\"#e4e4e4\"/>\n<line x1=\"" << fmt(f.x0 - 5) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(f.x0)
        << "\" y2=\"" << fmt(y) << "\" stroke=\"#333\"/>\n<text x=\"" << fmt(f.x0 - 8) << "\" y=\"" << fmt(y + 4)
        << "\" text-anchor=\"end\" font-size=\"12\">" << tick_text(t) << "</text>\n";
  }
  svg << "<text x=\"" << fmt((f.x0 + f.x1) / 2) << "\" y=\"" << fmt(f.y1 + 42)
      << "\" text-anchor=\"middle\" font-size=\"13\">" << escape(panel.x_label) << "</text>\n";
  svg << "<text transform=\"translate(" << fmt(ox + 18) << "," << fmt((f.y0 + f.y1) / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"13\">" << escape(panel.y_label) << "</text>\n";
  for (const auto& line : panel.vertical_lines) {
    if (!drawable(line.x, panel.log_x)) continue;
    const double x = f.px(line.x);
    svg << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(f.y0) << "\" x2=\"" << fmt(x) << "\" y2=\"" << fmt(f.y1)
        << "\" stroke=\"#444\" stroke-dasharray=\"6,4\"/>\n<text x=\"" << fmt(x + 4) << "\" y=\"" << fmt(f.y0 + 14)
        << "\" font-size=\"11\" fill=\"#444\">" << escape(line.label) << "</text>\n";
  }
}

// One point's marker (a crossed ring where marked) and its label.
void render_point(std::ostringstream& svg, const PlotPoint& p, double x, double y, const std::string& colour) {
  if (p.marked) {
    svg << "<circle cx=\"" << fmt(x) << "\" cy=\"" << fmt(y) << "\" r=\"6\" fill=\"white\" stroke=\"" << colour
        << "\" stroke-width=\"2\"/>\n<path d=\"M" << fmt(x - 4) << "," << fmt(y - 4) << " L" << fmt(x + 4) << ","
        << fmt(y + 4) << " M" << fmt(x - 4) << "," << fmt(y + 4) << " L" << fmt(x + 4) << "," << fmt(y - 4)
        << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n";
  } else {
    svg << "<circle cx=\"" << fmt(x) << "\" cy=\"" << fmt(y) << "\" r=\"4\" fill=\"" << colour << "\"/>\n";
  }
  if (!p.label.empty())
    svg << "<text x=\"" << fmt(x + 7) << "\" y=\"" << fmt(y - 6) << "\" font-size=\"11\" fill=\"" << colour << "\">"
        << escape(p.label) << "</text>\n";
}

// The bands first, under the series they connect; then each series' line and points.
void render_series(std::ostringstream& svg, const PlotPanel& panel, const PanelFrame& f,
                   const std::map<std::string, std::string>& colours) {
  auto polyline = [&](const PlotSeries& series) {
    std::string path;
    for (const auto& p : series.points)
      if (drawable(p.x, panel.log_x) && drawable(p.y, panel.log_y))
        path += (path.empty() ? "" : " ") + fmt(f.px(p.x)) + "," + fmt(f.py(p.y));
    return path;
  };
  for (const auto& series : panel.series)
    if (series.band && !polyline(series).empty())
      svg << "<polyline points=\"" << polyline(series) << "\" fill=\"none\" stroke=\"" << colours.at(series.name)
          << "\" stroke-width=\"" << kBandWidth << "\" stroke-opacity=\"0.5\" stroke-linejoin=\"round\" "
          << "stroke-linecap=\"round\"/>\n";
  for (const auto& series : panel.series) {
    if (series.band) continue;
    const std::string& colour = colours.at(series.name);
    const std::string path = polyline(series);
    if (!path.empty())
      svg << "<polyline points=\"" << path << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n";
    for (const auto& p : series.points)
      if (drawable(p.x, panel.log_x) && drawable(p.y, panel.log_y)) render_point(svg, p, f.px(p.x), f.py(p.y), colour);
  }
}

void render_panel(std::ostringstream& svg, const PlotPanel& panel, double ox, double oy,
                  const std::map<std::string, std::string>& colours) {
  PanelFrame f{ox + kLeft, ox + kPanelWidth - kRight, oy + kTop, oy + kPanelHeight - kBottom, {}, {}};
  svg << "<text x=\"" << fmt((f.x0 + f.x1) / 2) << "\" y=\"" << fmt(oy + 24)
      << "\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" << escape(panel.title) << "</text>\n";

  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  int hidden = 0;
  for (const auto& series : panel.series)
    for (const auto& p : series.points) {
      if (drawable(p.x, panel.log_x) && drawable(p.y, panel.log_y)) {
        xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
      } else {
        ++hidden;
      }
    }
  for (const auto& line : panel.vertical_lines)
    if (drawable(line.x, panel.log_x)) xmin = std::min(xmin, line.x), xmax = std::max(xmax, line.x);
  svg << "<rect x=\"" << fmt(f.x0) << "\" y=\"" << fmt(f.y0) << "\" width=\"" << fmt(f.x1 - f.x0) << "\" height=\""
      << fmt(f.y1 - f.y0) << "\" fill=\"none\" stroke=\"#333\"/>\n";
  if (!(xmin <= xmax) || !(ymin <= ymax)) {
    svg << "<text x=\"" << fmt((f.x0 + f.x1) / 2) << "\" y=\"" << fmt((f.y0 + f.y1) / 2)
        << "\" text-anchor=\"middle\" font-size=\"13\" fill=\"#777\">no data to show</text>\n";
    return;
  }
  f.ax.log = panel.log_x;
  f.ay.log = panel.log_y;
  f.ax.fit(xmin, xmax);
  f.ay.fit(ymin, ymax);
  render_axes(svg, panel, f, ox);
  render_series(svg, panel, f, colours);
  if (hidden > 0)  // above the frame's top right corner, clear of the points and line labels
    svg << "<text x=\"" << fmt(f.x1) << "\" y=\"" << fmt(f.y0 - 4) << "\" text-anchor=\"end\" font-size=\"11\" "
        << "fill=\"#777\">" << hidden << " point" << (hidden == 1 ? "" : "s") << " not shown (not "
        << (panel.log_x || panel.log_y ? "positive/finite" : "finite") << ")</text>\n";
}

// Splits `text` at blanks into lines of at most `width` characters (longer words stay whole).
std::vector<std::string> wrap(const std::string& text, std::size_t width) {
  std::vector<std::string> lines;
  std::string line, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    if (!line.empty() && line.size() + 1 + word.size() > width) lines.push_back(line), line.clear();
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ')
      flush_word();
    else
      word += c;
  }
  flush_word();
  if (!line.empty()) lines.push_back(line);
  return lines;
}

}  // namespace

std::string render_svg(const PlotFigure& figure) {
  std::map<std::string, std::string> colours;
  std::vector<std::string> names;
  std::set<std::string> bands;
  std::size_t palette_used = 0;
  for (const auto& panel : figure.panels)
    for (const auto& series : panel.series)
      if (!colours.count(series.name)) {
        colours[series.name] =
            series.band ? kBandColour : kPalette[palette_used++ % (sizeof kPalette / sizeof kPalette[0])];
        names.push_back(series.name);
        if (series.band) bands.insert(series.name);
      }
  const int columns = std::max(1, std::min<int>(figure.columns, std::max<std::size_t>(1, figure.panels.size())));
  const int rows = (static_cast<int>(figure.panels.size()) + columns - 1) / columns;
  const double width = columns * kPanelWidth;
  std::vector<std::string> notes;
  for (const auto& note : figure.notes)
    for (const auto& line : wrap(note, static_cast<std::size_t>(width / 6.6))) notes.push_back(line);
  const double header = 36 + 18.0 * notes.size();
  // Legend entries flow left to right, each as wide as its text, wrapping at the figure's width.
  std::vector<std::string> entries = names;
  if (!figure.marked_meaning.empty()) entries.push_back(figure.marked_meaning);
  std::vector<std::pair<double, double>> entry_at;  // (x, line) of each entry
  double next_x = 20;
  int line = 0;
  for (const auto& entry : entries) {
    const double entry_width = 36 + kLegendCharWidth * entry.size() + 24;
    if (next_x > 20 && next_x + entry_width > width - 10) next_x = 20, ++line;
    entry_at.push_back({next_x, line});
    next_x += entry_width;
  }
  const double legend = 20 + 22.0 * (line + 1);
  const double height = header + rows * kPanelHeight + legend;

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(width) << "\" height=\"" << fmt(height)
      << "\" viewBox=\"0 0 " << fmt(width) << " " << fmt(height)
      << "\" font-family=\"Helvetica, Arial, sans-serif\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg << "<text x=\"" << fmt(width / 2) << "\" y=\"24\" text-anchor=\"middle\" font-size=\"18\" font-weight=\"bold\">"
      << escape(figure.title) << "</text>\n";
  for (std::size_t k = 0; k < notes.size(); ++k)
    svg << "<text x=\"" << fmt(width / 2) << "\" y=\"" << fmt(44 + 18.0 * k)
        << "\" text-anchor=\"middle\" font-size=\"12\" fill=\"#333\">" << escape(notes[k]) << "</text>\n";
  for (std::size_t k = 0; k < figure.panels.size(); ++k)
    render_panel(svg, figure.panels[k], (k % columns) * kPanelWidth, header + (k / columns) * kPanelHeight, colours);

  // Legend.
  const double ly = header + rows * kPanelHeight + 16;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const double x = entry_at[k].first, y = ly + 22.0 * entry_at[k].second;
    if (k < names.size()) {
      const std::string& colour = colours[names[k]];
      if (bands.count(names[k]))
        svg << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(x + 28) << "\" y2=\"" << fmt(y)
            << "\" stroke=\"" << colour << "\" stroke-width=\"" << kBandWidth << "\" stroke-opacity=\"0.5\"/>\n";
      else
        svg << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(x + 28) << "\" y2=\"" << fmt(y)
            << "\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n<circle cx=\"" << fmt(x + 14) << "\" cy=\""
            << fmt(y) << "\" r=\"4\" fill=\"" << colour << "\"/>\n";
      svg << "<text x=\"" << fmt(x + 36) << "\" y=\"" << fmt(y + 4) << "\" font-size=\"13\">" << escape(names[k])
          << "</text>\n";
    } else {
      svg << "<circle cx=\"" << fmt(x + 14) << "\" cy=\"" << fmt(y) << "\" r=\"6\" fill=\"white\" stroke=\"#333\" "
          << "stroke-width=\"2\"/>\n<path d=\"M" << fmt(x + 10) << "," << fmt(y - 4) << " L" << fmt(x + 18) << ","
          << fmt(y + 4) << " M" << fmt(x + 10) << "," << fmt(y + 4) << " L" << fmt(x + 18) << "," << fmt(y - 4)
          << "\" stroke=\"#333\" stroke-width=\"2\"/>\n<text x=\"" << fmt(x + 36) << "\" y=\"" << fmt(y + 4)
          << "\" font-size=\"13\">" << escape(figure.marked_meaning) << "</text>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

void write_svg(const std::string& path, const PlotFigure& figure) { write_text_atomically(path, render_svg(figure)); }

}  // namespace fnopt
