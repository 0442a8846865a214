// Replay of a trajectory CSV (docs/design.md §10), in the layout of ../shared/data/arcsim/motions.csv.
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fnopt/boundary/trajectory.hpp>
#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// Handle positions at increasing times; linear in between, held outside.
class TableTrajectory : public HandleTrajectory {
 public:
  TableTrajectory(std::vector<double> times, std::vector<Vec3> positions, int handle_count, double speed)
      : times_(std::move(times)), positions_(std::move(positions)), handle_count_(handle_count), speed_(speed) {}

  int handle_count() const override { return handle_count_; }

  Vec3 position(int k, double t) const override {
    assert(k >= 0 && k < handle_count_);
    const double tau = speed_ * t;
    if (!(tau > times_.front())) return at(0, k);  // also a NaN time: never index past the end
    if (tau >= times_.back()) return at(times_.size() - 1, k);
    // times_[row - 1] <= tau < times_[row]
    const std::size_t row = std::upper_bound(times_.begin(), times_.end(), tau) - times_.begin();
    const double w = (tau - times_[row - 1]) / (times_[row] - times_[row - 1]);
    return (1.0 - w) * at(row - 1, k) + w * at(row, k);
  }

 private:
  const Vec3& at(std::size_t row, int k) const { return positions_[row * handle_count_ + k]; }

  std::vector<double> times_;
  std::vector<Vec3> positions_;  // row-major: row r, handle k at r * handle_count + k
  int handle_count_;
  double speed_;
};

// "file.csv#NAME" names the rows of one motion in a multi-motion file. A path that exists as
// written is taken whole, so a file name may itself contain '#'.
struct CsvSource {
  std::string file;
  std::optional<std::string> motion;
};

CsvSource parse_source(const std::string& spec) {
  const auto hash = spec.rfind('#');
  std::error_code ignored;
  if (hash == std::string::npos || std::filesystem::exists(spec, ignored)) return {spec, {}};
  return {spec.substr(0, hash), spec.substr(hash + 1)};
}

// K for a column named hK_x, hK_y or hK_z.
std::optional<int> handle_of_column(std::string_view name) {
  if (name.size() < 4 || name.front() != 'h' || name[name.size() - 2] != '_' ||
      std::string_view("xyz").find(name.back()) == std::string_view::npos)
    return std::nullopt;
  const auto digits = name.substr(1, name.size() - 3);
  int k = 0;
  if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }) || !parse_int(digits, k))
    return std::nullopt;
  return k;
}

struct CsvLine {
  int number;  // 1-based, for messages
  std::vector<std::string_view> fields;
};

// Reads and checks the CSV; every problem is one line "trajectory: <spec>: <problem>".
class CsvReader {
 public:
  CsvReader(std::string spec, int handle_count)
      : spec_(std::move(spec)), source_(parse_source(spec_)), handle_count_(handle_count) {}

  std::unique_ptr<HandleTrajectory> load(double speed) {
    read_lines();
    find_columns();
    const auto rows = selected_rows();
    std::vector<double> times;
    std::vector<Vec3> positions;
    for (const CsvLine* line : rows) {
      const double t = number(*line, time_column_);
      if (!times.empty() && !(t > times.back()))
        fail("line " + std::to_string(line->number) + ": time t_s = " + number_text(t) +
             " does not increase (previous row: " + number_text(times.back()) + ")");
      times.push_back(t);
      for (const auto& columns : handle_columns_)
        positions.emplace_back(number(*line, columns[0]), number(*line, columns[1]), number(*line, columns[2]));
    }
    return std::make_unique<TableTrajectory>(std::move(times), std::move(positions), handle_count_, speed);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const { throw Error("trajectory", spec_ + ": " + problem); }

  void read_lines() {
    std::error_code ignored;
    if (source_.motion && source_.motion->empty()) fail("no motion name after '#'");
    if (std::filesystem::is_directory(source_.file, ignored)) fail("is a directory, not a CSV file");
    std::ifstream in(source_.file, std::ios::binary);
    if (!in) fail("cannot open the file");
    text_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) fail("cannot read the file");
    // A byte-order mark, as spreadsheet programs write, is not part of the first column name.
    std::string_view content = text_;
    if (content.substr(0, 3) == "\xEF\xBB\xBF") content.remove_prefix(3);
    int number = 0;
    for (const auto raw : split(content, '\n')) {
      ++number;
      if (trim(raw).empty()) continue;
      CsvLine line{number, split(raw, ',')};
      for (auto& field : line.fields) field = trim(field);
      lines_.push_back(std::move(line));
    }
    if (lines_.empty()) fail("empty file; expected a header with t_s and hK_x,hK_y,hK_z columns");
  }

  std::optional<std::size_t> column(const std::string& name, bool required) const {
    const auto& header = lines_.front().fields;
    const auto found = std::find(header.begin(), header.end(), name);
    if (found == header.end()) {
      if (required)
        fail("missing column '" + name + "' (needs t_s and hK_x,hK_y,hK_z for each of the " + "scene's " +
             std::to_string(handle_count_) + " handle(s), K = 0, 1, ...)");
      return std::nullopt;
    }
    if (std::find(found + 1, header.end(), name) != header.end())
      fail("column '" + name + "' appears twice in the header");
    return static_cast<std::size_t>(found - header.begin());
  }

  void find_columns() {
    time_column_ = *column("t_s", true);
    motion_column_ = column("motion", false);
    for (int k = 0; k < handle_count_; ++k) {
      const std::string h = "h" + std::to_string(k);
      handle_columns_.push_back({*column(h + "_x", true), *column(h + "_y", true), *column(h + "_z", true)});
    }
    // Positions for a handle the scene does not have mean the file was made for another scene.
    for (const auto name : lines_.front().fields) {
      const auto k = handle_of_column(name);
      if (k && *k >= handle_count_)
        fail("has a column '" + std::string(name) + "' for handle " + std::to_string(*k) + ", but the scene has " +
             std::to_string(handle_count_) + " handle(s)");
    }
  }

  // The data rows to replay: all, or those of the motion named after '#'.
  std::vector<const CsvLine*> selected_rows() const {
    const std::size_t width = lines_.front().fields.size();
    std::vector<std::string_view> motions;  // distinct, in order of appearance
    std::vector<const CsvLine*> rows;
    for (auto line = lines_.begin() + 1; line != lines_.end(); ++line) {
      if (line->fields.size() != width)
        fail("line " + std::to_string(line->number) + ": expected " + std::to_string(width) +
             " fields as in the header, found " + std::to_string(line->fields.size()));
      if (motion_column_) {
        const auto motion = line->fields[*motion_column_];
        if (std::find(motions.begin(), motions.end(), motion) == motions.end()) motions.push_back(motion);
        if (source_.motion && motion != *source_.motion) continue;
      }
      rows.push_back(&*line);
    }
    std::string present;
    for (const auto motion : motions) present += (present.empty() ? "" : ", ") + std::string(motion);
    if (source_.motion && !motion_column_) fail("has no 'motion' column to pick '" + *source_.motion + "' from");
    if (source_.motion && rows.empty())
      fail("no rows with motion '" + *source_.motion + "' (present: " + present + ")");
    if (!source_.motion && motions.size() > 1)
      fail("holds " + std::to_string(motions.size()) + " motions (" + present + "); pick one with '" + source_.file +
           "#NAME'");
    if (rows.empty()) fail("no data rows; needs at least one row after the header");
    return rows;
  }

  double number(const CsvLine& line, std::size_t column) const {
    const auto text = line.fields[column];
    const std::string where =
        "line " + std::to_string(line.number) + ": column '" + std::string(lines_.front().fields[column]) + "': ";
    double value = 0.0;
    if (!parse_double(text, value)) fail(where + "'" + std::string(text) + "' is not a number");
    if (!std::isfinite(value)) fail(where + "value '" + std::string(text) + "' is not finite");
    return value;
  }

  std::string spec_;
  CsvSource source_;
  int handle_count_;
  std::string text_;            // the file; lines_ views into it
  std::vector<CsvLine> lines_;  // non-blank lines, the header first
  std::size_t time_column_ = 0;
  std::optional<std::size_t> motion_column_;
  std::vector<std::array<std::size_t, 3>> handle_columns_;
};

}  // namespace

std::unique_ptr<HandleTrajectory> load_trajectory_csv(const std::string& path, int handle_count, double speed) {
  assert(handle_count >= 0);
  require(std::isfinite(speed) && speed > 0.0, "speed", "must be a positive finite factor, got " + number_text(speed));
  return CsvReader(path, handle_count).load(speed);
}

}  // namespace fnopt
