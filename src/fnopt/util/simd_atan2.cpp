#include <cmath>

#include <fnopt/util/error.hpp>
#include <fnopt/util/simd_atan2.hpp>

namespace fnopt::simd {

// In simd_atan2_avx2.cpp and simd_atan2_avx512.cpp, compiled for those sets.
void atan2_array_avx2(const double* y, const double* x, double* out, long n);
void atan2_array_avx512(const double* y, const double* x, double* out, long n);

void atan2_array(SimdLevel level, const double* y, const double* x, double* out, long n) {
  if (!simd_level_supported(level)) throw Error("atan2_array: this CPU has no " + simd_level_name(level));
  switch (level) {
    case SimdLevel::Avx512:
      return atan2_array_avx512(y, x, out, n);
    case SimdLevel::Avx2:
      return atan2_array_avx2(y, x, out, n);
    case SimdLevel::Scalar:
      break;
  }
  for (long i = 0; i < n; ++i) out[i] = std::atan2(y[i], x[i]);
}

}  // namespace fnopt::simd
