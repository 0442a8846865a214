// angle_batch.hpp's kernels on AVX-512's lanes; this source is compiled for AVX-512 (CMakeLists.txt).
#include <fnopt/cloth/angle_lanes.hpp>
#include <fnopt/util/simd_lanes.hpp>

namespace fnopt {

AngleBatchKernels angle_batch_kernels_avx512() {
  using V = simd::Lanes8;
  return {V::kWidth, simd::angle_gradient_batches<V>, simd::angle_energy_batches<V>, simd::angle_hessian_batches<V>};
}

}  // namespace fnopt
