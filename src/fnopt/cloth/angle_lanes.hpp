#pragma once
// The body of angle_batch.hpp's kernels, on one lane group V (util/simd_lanes.hpp); included only
// by the sources compiled for V's instruction set (angle_batch_avx2.cpp, angle_batch_avx512.cpp).
// Line by line the operations of AngleKernel::gradient and AngleKernel::energy (angle_kernel.hpp),
// in the same order: dot products (u0 w0 + u1 w1) + u2 w2 as Eigen sums three terms, norms their
// square roots, cross products (u1 w2 - u2 w1, u2 w0 - u0 w2, u0 w1 - u1 w0).
#include <fnopt/cloth/angle_batch.hpp>
#include <fnopt/util/simd_atan2.hpp>

namespace fnopt::simd {

template <class V>
struct Vec3Lanes {
  V c[3];
};

template <class V>
V dot(const Vec3Lanes<V>& a, const Vec3Lanes<V>& b) {
  return (a.c[0] * b.c[0] + a.c[1] * b.c[1]) + a.c[2] * b.c[2];
}

template <class V>
Vec3Lanes<V> cross(const Vec3Lanes<V>& a, const Vec3Lanes<V>& b) {
  return {{a.c[1] * b.c[2] - a.c[2] * b.c[1], a.c[2] * b.c[0] - a.c[0] * b.c[2], a.c[0] * b.c[1] - a.c[1] * b.c[0]}};
}

// The edges u and w of one batch's stencils, gathered from x.
template <class V>
void gather_edges(const AngleBatchParams& params, const double* x, const int* offsets, Vec3Lanes<V>& u,
                  Vec3Lanes<V>& w) {
  constexpr int W = V::kWidth;
  for (int c = 0; c < 3; ++c) {
    const V x0 = V::gather(x + c, offsets), x1 = V::gather(x + c, offsets + W), x2 = V::gather(x + c, offsets + 2 * W);
    u.c[c] = x1 - x0;
    w.c[c] = params.corner ? x2 - x0 : x2 - x1;
  }
}

// AngleKernel::gradient on one batch: out holds 10 rows of W (angle_batch.hpp).
template <class V>
void angle_gradient_batch(const AngleBatchParams& params, const double* x, const int* offsets, double* out) {
  constexpr int W = V::kWidth;
  Vec3Lanes<V> u, w;
  gather_edges(params, x, offsets, u, w);
  const V one(1.0);
  const V inv_u = one / sqrt(dot(u, u)), inv_w = one / sqrt(dot(w, w));
  Vec3Lanes<V> uh, wh;
  for (int c = 0; c < 3; ++c) {
    uh.c[c] = inv_u * u.c[c];
    wh.c[c] = inv_w * w.c[c];
  }
  const Vec3Lanes<V> n = cross(uh, wh);
  const V sin = sqrt(dot(n, n)), cos = dot(uh, wh);
  const V theta = atan2(sin, cos);
  const V delta = theta - V(params.rest_angle);
  const V stiffness(params.stiffness), minus_stiffness(-params.stiffness);
  // dE/dc = -K delta / sin, or for theta0 = 0 below theta = 1e-3 its series -K (1 + theta^2/6).
  const V s = max(sin, V(1e-12));
  V dE_dc = minus_stiffness * delta / s;
  if (params.rest_angle == 0.0) {
    const V series = minus_stiffness * (one + theta * theta / V(6.0));
    dE_dc = select(theta < V(1e-3), series, dE_dc);
  }
  for (int c = 0; c < 3; ++c) {
    // grad_u E = dE/dc (w^ - c u^)/|u|, grad_w E = dE/dc (u^ - c w^)/|w|.
    const V gu = dE_dc * ((wh.c[c] - cos * uh.c[c]) * inv_u);
    const V gw = dE_dc * ((uh.c[c] - cos * wh.c[c]) * inv_w);
    if (params.corner) {  // u = x1 - x0, w = x2 - x0: g0 = -gu - gw, g1 = gu, g2 = gw
      (-gu - gw).store(out + c * W);
      gu.store(out + (3 + c) * W);
    } else {  // u = x1 - x0, w = x2 - x1: g0 = -gu, g1 = gu - gw, g2 = gw
      (-gu).store(out + c * W);
      (gu - gw).store(out + (3 + c) * W);
    }
    gw.store(out + (6 + c) * W);
  }
  (V(0.5) * stiffness * delta * delta).store(out + 9 * W);
}

// AngleKernel::energy on one batch: E = (K/2) (atan2(|u x w|, u.w) - theta0)^2 into W values.
template <class V>
void angle_energy_batch(const AngleBatchParams& params, const double* x, const int* offsets, double* out) {
  Vec3Lanes<V> u, w;
  gather_edges(params, x, offsets, u, w);
  const Vec3Lanes<V> n = cross(u, w);
  const V d = atan2(sqrt(dot(n, n)), dot(u, w)) - V(params.rest_angle);
  (V(0.5) * V(params.stiffness) * d * d).store(out);
}

template <class V>
void angle_gradient_batches(const AngleBatchParams& params, const double* x, const int* offsets, long batches,
                            double* out) {
  for (long b = 0; b < batches; ++b)
    angle_gradient_batch<V>(params, x, offsets + b * 3 * V::kWidth, out + b * 10 * V::kWidth);
}

template <class V>
void angle_energy_batches(const AngleBatchParams& params, const double* x, const int* offsets, long batches,
                          double* out) {
  for (long b = 0; b < batches; ++b)
    angle_energy_batch<V>(params, x, offsets + b * 3 * V::kWidth, out + b * V::kWidth);
}

}  // namespace fnopt::simd
