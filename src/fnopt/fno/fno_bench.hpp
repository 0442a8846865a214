#pragma once
// `fnopt bench fno`: timing of an FNO2d of the given options (the shipped model's, by default),
// float, at the given grids and batch 1 and 3, FFTW against torch::fft, forward and
// forward+backward, with the share of the forward time per stage. Takes well under a minute.
#include <ostream>
#include <vector>

#include <fnopt/fno/fno2d.hpp>

namespace fnopt {

// Sets LibTorch's intra-op threads to `threads` (≥ 1) and prints the table to `out`.
void run_fno_bench(std::ostream& out, int threads, const FNO2dOptions& options, const std::vector<int>& grids);

}  // namespace fnopt
