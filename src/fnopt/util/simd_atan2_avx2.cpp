// simd_atan2.hpp's atan2 on AVX2's lanes; this source is compiled for AVX2 (CMakeLists.txt).
#include <fnopt/util/simd_atan2.hpp>
#include <fnopt/util/simd_lanes.hpp>

namespace fnopt::simd {

void atan2_array_avx2(const double* y, const double* x, double* out, long n) { atan2_lanes<Lanes4>(y, x, out, n); }

}  // namespace fnopt::simd
