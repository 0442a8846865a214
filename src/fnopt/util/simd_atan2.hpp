#pragma once
// atan2(y, x) on a lane group of doubles (simd_lanes.hpp), after Cephes' atan (Moshier): the
// ratio t = |y|/|x| is reduced to a small z and an angle a with atan(t) = a + atan(z),
//   t > tan(3pi/8):        a = pi/2, z = -|x|/|y|
//   0.66 < t <= tan(3pi/8): a = pi/4, z = (|y| - |x|)/(|y| + |x|)
//   otherwise:             a = 0,    z = |y|/|x|
// (one division of the inputs themselves, never of a rounded t), and
//   atan(z) = z + z^3 P(z^2)/Q(z^2)
// with Cephes' rational minimax P/Q of degrees 4 and 5 (|z| <= 0.66). For x < 0 (sign bit set,
// -0 included) the angle is pi - a - atan(z); the sign is y's. To stay within one ulp the
// rounding errors of z's division and of the middle branch's sum and difference are carried as a
// correction z_error/(1 + z^2), each a is a double plus its rounding error, and a + atan(z) is
// summed as a head and a small part (tests/util/test_simd_atan2.cpp bounds the error in ulp).
// Exact for zeros of either sign; for finite inputs below about 1e307 in magnitude (the reduction
// forms |y| + |x| and 2.414 |x|): infinities are not handled.
#include <fnopt/util/simd_level.hpp>

namespace fnopt::simd {

// The rounding error of s = a + b (s the rounded sum): a + b - s, exactly (Knuth's TwoSum).
template <class V>
V two_sum_error(V a, V b, V s) {
  const V b_part = s - a;
  return (a - (s - b_part)) + (b - b_part);
}

template <class V>
V atan2(V y, V x) {
  const V ay = abs(y), ax = abs(x);
  const auto big = ay > V(2.414213562373095) * ax;
  const auto not_big = !big;
  const auto middle = not_big & (ay > V(0.66) * ax);
  // The middle branch's |y| -+ |x| and their rounding errors (Knuth's TwoSum); the other
  // branches' num and den are inputs, exact.
  const V difference = ay - ax, sum = ay + ax;
  const V difference_error = two_sum_error(ay, -ax, difference), sum_error = two_sum_error(ay, ax, sum);
  const V zero(0.0);
  const V num = select(big, -ax, select(middle, difference, ay));
  const V den = select(big, ay, select(middle, sum, ax));
  const V num_error = select(middle, difference_error, zero), den_error = select(middle, sum_error, zero);
  // z = num/den rounded, and z_error = (num + num_error)/(den + den_error) - z to first order: the
  // division's residual num - z den is exact with a fused multiply-add.
  const auto both_zero = (ay == zero) & (ax == zero);
  const V z = select(both_zero, zero, num / den);
  const V z_error = select(both_zero, zero, (fma(-z, den, num) + (num_error - z * den_error)) / den);
  const V z2 = z * z;
  const V p = fma(fma(fma(fma(V(-8.750608600031904122785e-1), z2, V(-1.615753718733365076637e1)), z2,
                          V(-7.500855792314704667340e1)),
                      z2, V(-1.228866684490136173410e2)),
                  z2, V(-6.485021904942025371773e1));
  const V q = fma(fma(fma(fma(z2 + V(2.485846490142306297962e1), z2, V(1.650270098316988542046e2)), z2,
                          V(4.328810604912902668951e2)),
                      z2, V(4.853903996359136964868e2)),
                  z2, V(1.945506571482613964425e2));
  // atan(z + z_error) = z + tail, tail = z^3 P/Q + z_error/(1 + z^2).
  const V tail = fma(z, z2 * p / q, z_error / (V(1.0) + z2));
  // The angle a, or pi - a for x < 0, as hi + lo.
  const auto negative_x = signbit(x);
  const V hi = select(big, V(1.5707963267948966),
                      select(middle, select(negative_x, V(2.356194490192345), V(0.7853981633974483)),
                             select(negative_x, V(3.141592653589793), zero)));
  const V lo = select(big, V(6.123233995736766e-17),
                      select(middle, select(negative_x, V(9.184850993605148e-17), V(3.061616997868383e-17)),
                             select(negative_x, V(1.2246467991473532e-16), zero)));
  const V signed_z = select(negative_x, -z, z), signed_tail = select(negative_x, -tail, tail);
  // hi + z with its rounding error (Fast2Sum: |hi| >= |z|, or hi = 0), then the small parts, so
  // that the result is rounded once more only.
  const V head = hi + signed_z;
  const V head_error = (hi - head) + signed_z;
  return copysign(head + (head_error + (signed_tail + lo)), y);
}

// out[i] = atan2(y[i], x[i]) for i < n on V's lanes, the last, partial lane group through a full one
// (its unused lanes compute atan2(0, 1)). For a source compiled for V's instruction set.
template <class V>
void atan2_lanes(const double* y, const double* x, double* out, long n) {
  long i = 0;
  for (; i + V::kWidth <= n; i += V::kWidth) atan2(V::load(y + i), V::load(x + i)).store(out + i);
  if (i == n) return;
  double ty[V::kWidth], tx[V::kWidth], tout[V::kWidth];
  for (int l = 0; l < V::kWidth; ++l) {
    ty[l] = i + l < n ? y[i + l] : 0.0;
    tx[l] = i + l < n ? x[i + l] : 1.0;
  }
  atan2(V::load(ty), V::load(tx)).store(tout);
  for (int l = 0; i + l < n; ++l) out[i + l] = tout[l];
}

// out[i] = atan2(y[i], x[i]) for i < n, on `level`'s lanes (std::atan2 for Scalar); the tests'
// and benchmarks' entry to the lanes' atan2.
void atan2_array(SimdLevel level, const double* y, const double* x, double* out, long n);

}  // namespace fnopt::simd
