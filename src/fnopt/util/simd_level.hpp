#pragma once
// The widest SIMD instruction set this CPU runs, picked at run time: the build is portable (no
// -march=native), so code for AVX2 or AVX-512 sits in sources compiled for that set alone
// (CMakeLists.txt: *_avx2.cpp, *_avx512.cpp) and is only called where the CPU and the OS support it.
#include <string>

namespace fnopt {

enum class SimdLevel {
  Scalar,  // plain C++, the reference
  Avx2,    // 4 doubles a lane group, with FMA
  Avx512,  // 8 doubles a lane group (AVX-512F), with FMA
};

// The widest level the CPU supports; Scalar where it supports neither.
SimdLevel best_simd_level();
// Whether this CPU runs `level`'s code.
bool simd_level_supported(SimdLevel level);
// "scalar", "avx2", "avx512".
std::string simd_level_name(SimdLevel level);

}  // namespace fnopt
