#include <cassert>

#include <fnopt/cloth/angle_batch.hpp>

namespace fnopt {

// In angle_batch_avx2.cpp and angle_batch_avx512.cpp, compiled for those sets.
AngleBatchKernels angle_batch_kernels_avx2();
AngleBatchKernels angle_batch_kernels_avx512();

AngleBatchKernels angle_batch_kernels(SimdLevel level) {
  assert(level != SimdLevel::Scalar && simd_level_supported(level));
  return level == SimdLevel::Avx512 ? angle_batch_kernels_avx512() : angle_batch_kernels_avx2();
}

}  // namespace fnopt
