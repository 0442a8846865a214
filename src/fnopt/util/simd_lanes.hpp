#pragma once
// Lane groups of doubles for the SIMD kernels: one type per instruction set, each with the same
// operations (arithmetic, sqrt, max, fused multiply-add, comparisons to a mask, select, gather),
// so that one kernel template serves every set. A type exists only where its set is enabled for
// the whole source (-mavx2 -mfma, -mavx512f -mfma: the *_avx2.cpp and *_avx512.cpp sources,
// simd_level.hpp), so any out-of-line copy of its functions is code for that set, called from
// that set's code only.
// GCC 12's AVX-512 intrinsics start some results from _mm512_undefined_pd(), which it then reports
// as uninitialised (GCC bug 105593, fixed in GCC 13); the reports point into <immintrin.h>'s headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop

namespace fnopt::simd {

#if defined(__AVX2__) && defined(__FMA__)
// 4 doubles (AVX2); a mask is a vector of all-ones or all-zeros lanes.
struct Lanes4 {
  static constexpr int kWidth = 4;
  struct Mask {
    __m256d m;
    Mask operator&(Mask o) const { return {_mm256_and_pd(m, o.m)}; }
    Mask operator|(Mask o) const { return {_mm256_or_pd(m, o.m)}; }
    Mask operator!() const { return {_mm256_xor_pd(m, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }
  };
  __m256d v;

  Lanes4() = default;
  Lanes4(__m256d value) : v(value) {}
  Lanes4(double value) : v(_mm256_set1_pd(value)) {}
  static Lanes4 load(const double* p) { return _mm256_loadu_pd(p); }
  void store(double* p) const { _mm256_storeu_pd(p, v); }
  // Lane l reads base[offsets[l]].
  static Lanes4 gather(const double* base, const int* offsets) {
    return _mm256_i32gather_pd(base, _mm_loadu_si128(reinterpret_cast<const __m128i*>(offsets)), 8);
  }

  friend Lanes4 operator+(Lanes4 a, Lanes4 b) { return _mm256_add_pd(a.v, b.v); }
  friend Lanes4 operator-(Lanes4 a, Lanes4 b) { return _mm256_sub_pd(a.v, b.v); }
  friend Lanes4 operator*(Lanes4 a, Lanes4 b) { return _mm256_mul_pd(a.v, b.v); }
  friend Lanes4 operator/(Lanes4 a, Lanes4 b) { return _mm256_div_pd(a.v, b.v); }
  friend Lanes4 operator-(Lanes4 a) { return _mm256_xor_pd(a.v, _mm256_set1_pd(-0.0)); }
  friend Lanes4 sqrt(Lanes4 a) { return _mm256_sqrt_pd(a.v); }
  friend Lanes4 max(Lanes4 a, Lanes4 b) { return _mm256_max_pd(a.v, b.v); }
  friend Lanes4 abs(Lanes4 a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v); }
  // a * b + c, rounded once.
  friend Lanes4 fma(Lanes4 a, Lanes4 b, Lanes4 c) { return _mm256_fmadd_pd(a.v, b.v, c.v); }
  // |a| with the sign bit of b.
  friend Lanes4 copysign(Lanes4 a, Lanes4 b) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    return _mm256_or_pd(_mm256_andnot_pd(sign, a.v), _mm256_and_pd(sign, b.v));
  }
  // Lanes whose sign bit is set (-0.0 included).
  friend Mask signbit(Lanes4 a) {
    return {_mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_setzero_si256(), _mm256_castpd_si256(a.v)))};
  }
  friend Mask operator<(Lanes4 a, Lanes4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask operator>(Lanes4 a, Lanes4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
  friend Mask operator==(Lanes4 a, Lanes4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_EQ_OQ)}; }
  // mask ? a : b, lane by lane.
  friend Lanes4 select(Mask mask, Lanes4 a, Lanes4 b) { return _mm256_blendv_pd(b.v, a.v, mask.m); }
};
#endif

#if defined(__AVX512F__) && defined(__FMA__)
// 8 doubles (AVX-512F); a mask is one bit a lane.
struct Lanes8 {
  static constexpr int kWidth = 8;
  struct Mask {
    __mmask8 m;
    Mask operator&(Mask o) const { return {static_cast<__mmask8>(m & o.m)}; }
    Mask operator|(Mask o) const { return {static_cast<__mmask8>(m | o.m)}; }
    Mask operator!() const { return {static_cast<__mmask8>(~m)}; }
  };
  __m512d v;

  Lanes8() = default;
  Lanes8(__m512d value) : v(value) {}
  Lanes8(double value) : v(_mm512_set1_pd(value)) {}
  static Lanes8 load(const double* p) { return _mm512_loadu_pd(p); }
  void store(double* p) const { _mm512_storeu_pd(p, v); }
  // Lane l reads base[offsets[l]].
  static Lanes8 gather(const double* base, const int* offsets) {
    return _mm512_i32gather_pd(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(offsets)), base, 8);
  }

  friend Lanes8 operator+(Lanes8 a, Lanes8 b) { return _mm512_add_pd(a.v, b.v); }
  friend Lanes8 operator-(Lanes8 a, Lanes8 b) { return _mm512_sub_pd(a.v, b.v); }
  friend Lanes8 operator*(Lanes8 a, Lanes8 b) { return _mm512_mul_pd(a.v, b.v); }
  friend Lanes8 operator/(Lanes8 a, Lanes8 b) { return _mm512_div_pd(a.v, b.v); }
  friend Lanes8 operator-(Lanes8 a) { return bits_xor(a.v, _mm512_set1_pd(-0.0)); }
  friend Lanes8 sqrt(Lanes8 a) { return _mm512_sqrt_pd(a.v); }
  friend Lanes8 max(Lanes8 a, Lanes8 b) { return _mm512_max_pd(a.v, b.v); }
  friend Lanes8 abs(Lanes8 a) { return _mm512_abs_pd(a.v); }
  // a * b + c, rounded once.
  friend Lanes8 fma(Lanes8 a, Lanes8 b, Lanes8 c) { return _mm512_fmadd_pd(a.v, b.v, c.v); }
  // |a| with the sign bit of b.
  friend Lanes8 copysign(Lanes8 a, Lanes8 b) {
    const __m512i sign = _mm512_castpd_si512(_mm512_set1_pd(-0.0));
    const __m512i magnitude = _mm512_castpd_si512(_mm512_set1_pd(__builtin_bit_cast(double, 0x7fffffffffffffffULL)));
    return _mm512_castsi512_pd(_mm512_or_si512(_mm512_and_si512(magnitude, _mm512_castpd_si512(a.v)),
                                               _mm512_and_si512(sign, _mm512_castpd_si512(b.v))));
  }
  // Lanes whose sign bit is set (-0.0 included).
  friend Mask signbit(Lanes8 a) { return {_mm512_cmplt_epi64_mask(_mm512_castpd_si512(a.v), _mm512_setzero_si512())}; }
  friend Mask operator<(Lanes8 a, Lanes8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask operator>(Lanes8 a, Lanes8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)}; }
  friend Mask operator==(Lanes8 a, Lanes8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_EQ_OQ)}; }
  // mask ? a : b, lane by lane.
  friend Lanes8 select(Mask mask, Lanes8 a, Lanes8 b) { return _mm512_mask_blend_pd(mask.m, b.v, a.v); }

 private:
  // Bitwise xor of two vectors of doubles (AVX-512F has it on integers only; DQ on doubles).
  static __m512d bits_xor(__m512d a, __m512d b) {
    return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b)));
  }
};
#endif

}  // namespace fnopt::simd
