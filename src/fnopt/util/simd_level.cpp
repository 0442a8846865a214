#include <fnopt/util/simd_level.hpp>

namespace fnopt {

bool simd_level_supported(SimdLevel level) {
  // libgcc's CPU check includes the OS's saving of the wider registers (XGETBV). Its data are
  // filled by a constructor; the explicit call covers a use from another static constructor.
  __builtin_cpu_init();
  switch (level) {
    case SimdLevel::Scalar:
      return true;
    case SimdLevel::Avx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case SimdLevel::Avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma");
  }
  return false;
}

SimdLevel best_simd_level() {
  static const SimdLevel best = simd_level_supported(SimdLevel::Avx512) ? SimdLevel::Avx512
                                : simd_level_supported(SimdLevel::Avx2) ? SimdLevel::Avx2
                                                                        : SimdLevel::Scalar;
  return best;
}

std::string simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
      return "scalar";
    case SimdLevel::Avx2:
      return "avx2";
    case SimdLevel::Avx512:
      return "avx512";
  }
  return "unknown";
}

}  // namespace fnopt
