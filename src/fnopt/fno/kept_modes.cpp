#include <fnopt/fno/kept_modes.hpp>

#include <algorithm>
#include <string>

#include <fnopt/util/error.hpp>

namespace fnopt::fno {

KeptModes kept_modes(int64_t rows, int64_t cols, int64_t modes_x, int64_t modes_y) {
  require(rows > 0 && cols > 0, "spectral convolution",
          "grid must be non-empty, got " + std::to_string(rows) + "x" + std::to_string(cols));
  require(modes_x > 0 && modes_x % 2 == 0 && modes_y > 0 && modes_y % 2 == 0, "spectral convolution",
          "modes must be positive and even, got " + std::to_string(modes_x) + "x" + std::to_string(modes_y));
  KeptModes m;
  m.rows = rows;
  m.cols = cols;
  m.lowest_row_freq = std::max(-modes_x / 2, -rows / 2);
  const int64_t highest_row_freq = std::min(modes_x / 2 - 1, (rows - 1) / 2);
  m.kept_rows = highest_row_freq - m.lowest_row_freq + 1;
  m.kept_cols = std::min(modes_y / 2 + 1, cols / 2 + 1);
  m.weight_row_offset = m.lowest_row_freq + modes_x / 2;
  return m;
}

}  // namespace fnopt::fno
