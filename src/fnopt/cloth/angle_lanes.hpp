#pragma once
// The body of angle_batch.hpp's kernels, on one lane group V (util/simd_lanes.hpp); included only
// by the sources compiled for V's instruction set (angle_batch_avx2.cpp, angle_batch_avx512.cpp).
// Line by line the operations of AngleKernel::gradient, hessian (unprojected) and energy (angle_kernel.hpp),
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

// AngleKernel's Local on one batch: the unit edges, cos theta, theta - theta0, dE/dc and the
// inverse lengths, each as the scalar kernel computes it.
template <class V>
struct AngleLocal {
  Vec3Lanes<V> uh, wh;
  V inv_u, inv_w, sin, cos, theta, delta, dE_dc;
};

template <class V>
AngleLocal<V> angle_local(const AngleBatchParams& params, const double* x, const int* offsets) {
  Vec3Lanes<V> u, w;
  gather_edges(params, x, offsets, u, w);
  AngleLocal<V> l;
  const V one(1.0);
  l.inv_u = one / sqrt(dot(u, u));
  l.inv_w = one / sqrt(dot(w, w));
  for (int c = 0; c < 3; ++c) {
    l.uh.c[c] = l.inv_u * u.c[c];
    l.wh.c[c] = l.inv_w * w.c[c];
  }
  const Vec3Lanes<V> n = cross(l.uh, l.wh);
  l.sin = sqrt(dot(n, n));
  l.cos = dot(l.uh, l.wh);
  l.theta = atan2(l.sin, l.cos);
  l.delta = l.theta - V(params.rest_angle);
  // dE/dc = -K delta / sin, or for theta0 = 0 below theta = 1e-3 its series -K (1 + theta^2/6).
  const V minus_stiffness(-params.stiffness);
  l.dE_dc = minus_stiffness * l.delta / max(l.sin, V(1e-12));
  if (params.rest_angle == 0.0)
    l.dE_dc = select(l.theta < V(1e-3), minus_stiffness * (one + l.theta * l.theta / V(6.0)), l.dE_dc);
  return l;
}

// AngleKernel::gradient on one batch: out holds 10 rows of W (angle_batch.hpp).
template <class V>
void angle_gradient_batch(const AngleBatchParams& params, const double* x, const int* offsets, double* out) {
  constexpr int W = V::kWidth;
  const AngleLocal<V> l = angle_local<V>(params, x, offsets);
  for (int c = 0; c < 3; ++c) {
    // grad_u E = dE/dc (w^ - c u^)/|u|, grad_w E = dE/dc (u^ - c w^)/|w|.
    const V gu = l.dE_dc * ((l.wh.c[c] - l.cos * l.uh.c[c]) * l.inv_u);
    const V gw = l.dE_dc * ((l.uh.c[c] - l.cos * l.wh.c[c]) * l.inv_w);
    if (params.corner) {  // u = x1 - x0, w = x2 - x0: g0 = -gu - gw, g1 = gu, g2 = gw
      (-gu - gw).store(out + c * W);
      gu.store(out + (3 + c) * W);
    } else {  // u = x1 - x0, w = x2 - x1: g0 = -gu, g1 = gu - gw, g2 = gw
      (-gu).store(out + c * W);
      (gu - gw).store(out + (3 + c) * W);
    }
    gw.store(out + (6 + c) * W);
  }
  (V(0.5) * V(params.stiffness) * l.delta * l.delta).store(out + 9 * W);
}

// AngleKernel::hessian(x, H, false) on one batch: out holds 81 rows of W, entry (r, c) of the 9x9
// in row 9c + r (column-major, as Eigen stores it). The 6x6 in (u, w) as AngleKernel::edge_hessian,
//   uu(p,q) = E'' dc_du[p] dc_du[q] + ku  (3c uh[p] uh[q] - wh[p] uh[q] - uh[p] wh[q] - c [p = q]),
//   ww(p,q) = E'' dc_dw[p] dc_dw[q] + kw  (3c wh[p] wh[q] - uh[p] wh[q] - wh[p] uh[q] - c [p = q]),
//   uw(p,q) = E'' dc_du[p] dc_dw[q] + kuw ([p = q] - uh[p] uh[q] - wh[p] wh[q] + c uh[p] wh[q]), wu = uw^T,
// (E' = dE/dc, ku = E'/|u|^2, kw = E'/|w|^2, kuw = E'/(|u||w|)), then mapped to the vertices' blocks as
// AngleKernel::to_vertices does for the Corner and Hinge layouts.
template <class V>
void angle_hessian_batch(const AngleBatchParams& params, const double* x, const int* offsets, double* out) {
  constexpr int W = V::kWidth;
  const AngleLocal<V> l = angle_local<V>(params, x, offsets);
  const V stiffness(params.stiffness), c = l.cos;
  // d2E/dc2 = K (1/sin^2 - delta cos/sin^3), or for theta0 = 0 below theta = 1e-3 its series
  // K (1/3 + 2 theta^2/15).
  const V s = max(l.sin, V(1e-12));
  V d2E_dc2 = stiffness * (V(1.0) / (s * s) - l.delta * c / (s * s * s));
  if (params.rest_angle == 0.0)
    d2E_dc2 = select(l.theta < V(1e-3), stiffness * (V(1.0 / 3.0) + V(2.0) * (l.theta * l.theta) / V(15.0)), d2E_dc2);
  Vec3Lanes<V> dc_du, dc_dw;
  for (int k = 0; k < 3; ++k) {
    dc_du.c[k] = (l.wh.c[k] - c * l.uh.c[k]) * l.inv_u;
    dc_dw.c[k] = (l.uh.c[k] - c * l.wh.c[k]) * l.inv_w;
  }
  const V ku = l.dE_dc * l.inv_u * l.inv_u, kw = l.dE_dc * l.inv_w * l.inv_w, kuw = l.dE_dc * l.inv_u * l.inv_w;
  const V three_c = V(3.0) * c;
  const Vec3Lanes<V>&uh = l.uh, &wh = l.wh;
  V uu[3][3], ww[3][3], uw[3][3];
  for (int q = 0; q < 3; ++q)
    for (int p = 0; p < 3; ++p) {
      const V id(p == q ? 1.0 : 0.0);
      uu[p][q] = d2E_dc2 * dc_du.c[p] * dc_du.c[q] +
                 ku * (three_c * uh.c[p] * uh.c[q] - wh.c[p] * uh.c[q] - uh.c[p] * wh.c[q] - c * id);
      ww[p][q] = d2E_dc2 * dc_dw.c[p] * dc_dw.c[q] +
                 kw * (three_c * wh.c[p] * wh.c[q] - uh.c[p] * wh.c[q] - wh.c[p] * uh.c[q] - c * id);
      uw[p][q] = d2E_dc2 * dc_du.c[p] * dc_dw.c[q] +
                 kuw * (id - uh.c[p] * uh.c[q] - wh.c[p] * wh.c[q] + c * uh.c[p] * wh.c[q]);
    }
  // Block (i, j) of the 9x9 and its transpose (j, i).
  auto set = [&](int i, int j, int p, int q, V value) {
    value.store(out + (9 * (3 * j + q) + 3 * i + p) * W);
    if (i != j) value.store(out + (9 * (3 * i + p) + 3 * j + q) * W);
  };
  for (int q = 0; q < 3; ++q)
    for (int p = 0; p < 3; ++p) {
      const V wu = uw[q][p];
      if (params.corner) {  // u = x1 - x0, w = x2 - x0
        set(0, 0, p, q, (uu[p][q] + uw[p][q]) + (wu + ww[p][q]));
        set(0, 1, p, q, -uu[p][q] - wu);
        set(1, 1, p, q, uu[p][q]);
        set(0, 2, p, q, -uw[p][q] - ww[p][q]);
        set(1, 2, p, q, uw[p][q]);
      } else {  // u = x1 - x0, w = x2 - x1
        set(0, 0, p, q, uu[p][q]);
        set(0, 1, p, q, -(uu[p][q] - uw[p][q]));
        set(1, 1, p, q, (uu[p][q] - uw[p][q]) - (wu - ww[p][q]));
        set(0, 2, p, q, -uw[p][q]);
        set(1, 2, p, q, uw[p][q] - ww[p][q]);
      }
      set(2, 2, p, q, ww[p][q]);
    }
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
void angle_hessian_batches(const AngleBatchParams& params, const double* x, const int* offsets, long batches,
                           double* out) {
  for (long b = 0; b < batches; ++b)
    angle_hessian_batch<V>(params, x, offsets + b * 3 * V::kWidth, out + b * 81 * V::kWidth);
}

template <class V>
void angle_energy_batches(const AngleBatchParams& params, const double* x, const int* offsets, long batches,
                          double* out) {
  for (long b = 0; b < batches; ++b) angle_energy_batch<V>(params, x, offsets + b * 3 * V::kWidth, out + b * V::kWidth);
}

}  // namespace fnopt::simd
