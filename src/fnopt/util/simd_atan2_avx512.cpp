// simd_atan2.hpp's atan2 on AVX-512's lanes; this source is compiled for AVX-512 (CMakeLists.txt).
#include <fnopt/util/simd_atan2.hpp>
#include <fnopt/util/simd_lanes.hpp>

namespace fnopt::simd {

void atan2_array_avx512(const double* y, const double* x, double* out, long n) {
  using V = Lanes8;
  long i = 0;
  for (; i + V::kWidth <= n; i += V::kWidth) atan2(V::load(y + i), V::load(x + i)).store(out + i);
  if (i == n) return;
  // The last, partial lane group through a full one (its unused lanes compute atan2(0, 1)).
  double ty[V::kWidth], tx[V::kWidth], tout[V::kWidth];
  for (int l = 0; l < V::kWidth; ++l) {
    ty[l] = i + l < n ? y[i + l] : 0.0;
    tx[l] = i + l < n ? x[i + l] : 1.0;
  }
  atan2(V::load(ty), V::load(tx)).store(tout);
  for (int l = 0; i + l < n; ++l) out[i + l] = tout[l];
}

}  // namespace fnopt::simd
