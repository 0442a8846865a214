#pragma once
// Handle vertex sets (docs/design.md §3): the vertices whose positions are prescribed.
#include <string>
#include <utility>
#include <vector>

#include <fnopt/cloth/grid.hpp>

namespace fnopt {

struct HandleSet {
  std::string name;           // preset name, or "vertices" for an explicit list
  std::vector<int> vertices;  // grid vertex indices i*cols + j, in handle order (handle 0, 1, ...)
};

// Presets: corner (the two top corners, handle 0 = (0,0), handle 1 = (0,C-1): the benchmark),
// diagonal, mid-edge, corner-center, single-mid-edge, single-center (see handles.cpp for the
// exact vertices), and none (a released cloth, no handle). Throws Error("handles", "unknown preset ...") listing the valid names.
HandleSet handle_preset(const Grid& grid, const std::string& preset);

// Explicit list "i,j;i,j;..." of (row, column) pairs. Throws Error("handle-vertices", "...")
// for a malformed entry, an index out of range or a duplicate.
HandleSet handle_vertices_from_list(const Grid& grid, const std::string& list);

// The (row, column) pairs of an explicit list, checked for syntax only (blanks around numbers
// allowed, no empty entry, no negative index): what a scene file can check before it knows
// the grid; a pair given twice is rejected too. Throws Error("handle-vertices", "...").
std::vector<std::pair<int, int>> parse_handle_list(const std::string& list);

std::vector<std::string> handle_preset_names();

}  // namespace fnopt
