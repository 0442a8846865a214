// simd_atan2.hpp's atan2 on AVX-512's lanes; this source is compiled for AVX-512 (CMakeLists.txt).
#include <fnopt/util/simd_atan2.hpp>
#include <fnopt/util/simd_lanes.hpp>

namespace fnopt::simd {

void atan2_array_avx512(const double* y, const double* x, double* out, long n) { atan2_lanes<Lanes8>(y, x, out, n); }

}  // namespace fnopt::simd
