#include <gtest/gtest.h>

#include <fnopt/util/simd_level.hpp>

namespace fnopt {
namespace {

TEST(SimdLevel, BestIsSupportedAndScalarAlwaysIs) {
  EXPECT_TRUE(simd_level_supported(SimdLevel::Scalar));
  EXPECT_TRUE(simd_level_supported(best_simd_level()));
  // AVX-512 machines have AVX2 as well, so the best level implies every narrower one.
  if (best_simd_level() == SimdLevel::Avx512) {
    EXPECT_TRUE(simd_level_supported(SimdLevel::Avx2));
  }
}

TEST(SimdLevel, Names) {
  EXPECT_EQ(simd_level_name(SimdLevel::Scalar), "scalar");
  EXPECT_EQ(simd_level_name(SimdLevel::Avx2), "avx2");
  EXPECT_EQ(simd_level_name(SimdLevel::Avx512), "avx512");
}

}  // namespace
}  // namespace fnopt
