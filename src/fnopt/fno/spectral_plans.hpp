#pragma once
// FFTW plans of the spectral convolution, created once per grid shape and reused.
//
// A 2-D transform of one [R, C] channel is split into two 1-D passes so that the pass along
// the first axis only runs on the kept columns (kept_cols of the C/2 + 1; 5 of 51 at 100²
// with 8 modes): forward = r2c along every row, then a complex DFT down the kept columns;
// backward = complex inverse DFT down the kept columns, then c2r along every row. Plans are
// per channel (not per batch·channels), executed with FFTW's new-array functions on each
// channel's slice, so one plan serves every batch size and channel count.
#include <cstdint>

#include <fnopt/fno/fftw_traits.hpp>

namespace fnopt::fno {

template <typename Real>
struct SpectralPlans {
  typename Fftw<Real>::Plan rows_forward;   // R real rows of length C → [R, C/2+1] complex
  typename Fftw<Real>::Plan cols_forward;   // in place, DFT of length R down kept_cols columns
  typename Fftw<Real>::Plan cols_backward;  // in place, inverse DFT down kept_cols columns
  typename Fftw<Real>::Plan rows_backward;  // [R, C/2+1] complex → R real rows (destroys input)
};

// Plans for one [rows, cols] channel, keyed by (rows, cols, kept_cols). Thread-safe: FFTW's
// planner is not, so creation is serialised; the returned plans live for the whole process
// and may be executed concurrently on different arrays. Execution arrays must be aligned
// like fftw_malloc's (Fftw<Real>::alignment_of(p) == 0).
template <typename Real>
const SpectralPlans<Real>& spectral_plans(int64_t rows, int64_t cols, int64_t kept_cols);

}  // namespace fnopt::fno
