#pragma once
// `fnopt bench fno`: timing of the FNO2d (FNOpt's configuration, float) at 32², 64², 100² and
// batch 1 and 3, FFTW against torch::fft, forward and forward+backward, with the share of the
// forward time per stage. Takes well under a minute.
#include <ostream>

namespace fnopt {

// Sets LibTorch's intra-op threads to `threads` (≥ 1) and prints the table to `out`.
void run_fno_bench(std::ostream& out, int threads);

}  // namespace fnopt
