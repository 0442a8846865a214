#pragma once
// Which BLAS LibTorch's dense layers really run on. Debian's libtorch reports BLAS_INFO=generic
// and calls whatever provides libblas.so.3; the reference BLAS makes the FNO's 1×1 layers
// several times slower than OpenBLAS (docs/design.md §9), so this is checked at run time.
#include <string>

namespace fnopt::fno {

// OpenBLAS's configuration string when OpenBLAS is loaded, else a warning naming the fix.
std::string runtime_blas();

// The BLAS_INFO entry of torch::show_config(), e.g. "BLAS_INFO=generic".
std::string torch_blas_info();

}  // namespace fnopt::fno
