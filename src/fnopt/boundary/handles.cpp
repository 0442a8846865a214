#include <fnopt/boundary/handles.hpp>

#include <algorithm>

#include <fnopt/util/error.hpp>
#include <fnopt/util/parse_text.hpp>

namespace fnopt {
namespace {

// The presets on an R x C grid, as (row, column) with integer division; row 0 is the top edge
// (rest z = 0), column 0 the left edge (rest x = 0). The paper's names:
//   corner           (0, 0), (0, C-1)                    the two top corners: the benchmark,
//                                                        the ARCSim handles 0 and 1
//   diagonal         (0, 0), (R-1, C-1)                  top-left and bottom-right corners
//   mid-edge         ((R-1)/2, 0), ((R-1)/2, C-1)        middles of the left and right edges
//   corner-center    (0, 0), ((R-1)/2, (C-1)/2)          top-left corner and the centre
//   single-mid-edge  (0, (C-1)/2)                        middle of the top edge
//   single-center    ((R-1)/2, (C-1)/2)                  the centre
std::vector<std::pair<int, int>> preset_cells(const std::string& preset, int R, int C) {
  const int mid_row = (R - 1) / 2, mid_col = (C - 1) / 2;
  if (preset == "corner") return {{0, 0}, {0, C - 1}};
  if (preset == "diagonal") return {{0, 0}, {R - 1, C - 1}};
  if (preset == "mid-edge") return {{mid_row, 0}, {mid_row, C - 1}};
  if (preset == "corner-center") return {{0, 0}, {mid_row, mid_col}};
  if (preset == "single-mid-edge") return {{0, mid_col}};
  if (preset == "single-center") return {{mid_row, mid_col}};
  return {};
}

}  // namespace

std::vector<std::string> handle_preset_names() {
  return {"corner", "diagonal", "mid-edge", "corner-center", "single-mid-edge", "single-center", "none"};
}

HandleSet handle_preset(const Grid& grid, const std::string& preset) {
  const auto cells = preset_cells(preset, grid.rows, grid.cols);
  require(!cells.empty() || preset == "none", "handles", "unknown preset '" + preset + "' (valid: " + joined(handle_preset_names()) + ")");
  HandleSet set{preset, {}};
  for (const auto& [i, j] : cells) set.vertices.push_back(grid.index(i, j));
  return set;
}

std::vector<std::pair<int, int>> parse_handle_list(const std::string& list) {
  const std::string field = "handle-vertices";
  require(!trim(list).empty(), field, "empty list; expected \"i,j;i,j;...\"");
  std::vector<std::pair<int, int>> cells;
  for (const auto entry : split(list, ';')) {
    const auto numbers = split(entry, ',');
    int i = 0, j = 0;
    require(numbers.size() == 2 && parse_int(numbers[0], i) && parse_int(numbers[1], j), field,
            "entry '" + std::string(trim(entry)) + "' is not \"row,column\" (two integers)");
    require(i >= 0 && j >= 0, field, "entry '" + std::string(trim(entry)) + "' has a negative index");
    require(std::find(cells.begin(), cells.end(), std::pair{i, j}) == cells.end(), field,
            "vertex (" + std::to_string(i) + "," + std::to_string(j) + ") is listed twice");
    cells.emplace_back(i, j);
  }
  return cells;
}

HandleSet handle_vertices_from_list(const Grid& grid, const std::string& list) {
  HandleSet set{"vertices", {}};
  for (const auto& [i, j] : parse_handle_list(list)) {
    require(i < grid.rows && j < grid.cols, "handle-vertices",
            "vertex (" + std::to_string(i) + "," + std::to_string(j) + ") is outside the " + std::to_string(grid.rows) +
                "x" + std::to_string(grid.cols) + " grid (rows 0.." + std::to_string(grid.rows - 1) + ", columns 0.." +
                std::to_string(grid.cols - 1) + ")");
    set.vertices.push_back(grid.index(i, j));
  }
  return set;
}

}  // namespace fnopt
