#pragma once
// Which Fourier modes a spectral convolution keeps on a given grid (docs/design.md §4).
//
// A layer with modes (mx, my) keeps row frequencies kx ∈ [−mx/2, mx/2) and half-spectrum
// column frequencies ky ∈ [0, my/2], intersected with the frequencies the grid itself has
// (numpy.fft.fftfreq convention: an even R has kx ∈ [−R/2, R/2), an odd R has
// kx ∈ [−(R−1)/2, (R−1)/2]; the half spectrum has ky ∈ [0, ⌊C/2⌋]). On a grid smaller than
// the modes the layer therefore keeps the whole spectrum, each frequency exactly once.
#include <cstdint>

namespace fnopt::fno {

struct KeptModes {
  int64_t rows = 0;               // R, grid size along the first axis
  int64_t cols = 0;               // C, grid size along the second (half-spectrum) axis
  int64_t lowest_row_freq = 0;    // the smallest kept kx (≤ 0)
  int64_t kept_rows = 0;          // kept kx: lowest_row_freq, ..., lowest_row_freq + kept_rows − 1
  int64_t kept_cols = 0;          // number of kept ky: 0, ..., kept_cols − 1
  int64_t weight_row_offset = 0;  // index of lowest_row_freq on the weight's kx axis (kx + mx/2)

  int64_t half_cols() const { return cols / 2 + 1; }
  int64_t kept_count() const { return kept_rows * kept_cols; }
  // Row of the full DFT holding the k-th kept row frequency.
  int64_t grid_row(int64_t k) const { return (lowest_row_freq + k + rows) % rows; }
  // Whether column ky is its own mirror image in a real signal's spectrum (ky = 0, and
  // ky = C/2 for even C): an inverse real transform counts it once and drops its imaginary
  // part, all other columns stand for themselves and their conjugates (count twice).
  bool self_conjugate_col(int64_t ky) const { return ky == 0 || 2 * ky == cols; }
};

// Throws fnopt::Error unless rows, cols, modes_x and modes_y are positive and modes are even.
KeptModes kept_modes(int64_t rows, int64_t cols, int64_t modes_x, int64_t modes_y);

}  // namespace fnopt::fno
