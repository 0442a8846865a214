#pragma once
// An independent, deliberately naive reference for the spectral convolution: direct DFT sums
// in double precision, written from the definition in fno/spectral_conv2d.hpp and
// docs/design.md §4 without sharing any code with fno/.
#include <torch/torch.h>

#include <cmath>
#include <complex>
#include <vector>

namespace fnopt::test {

// Frequency of DFT index `index` on a grid of n points, numpy.fft.fftfreq(n) * n.
inline int64_t signed_frequency(int64_t index, int64_t n) { return index < (n + 1) / 2 ? index : index - n; }

// exp(sign · 2πi · k·p / n), with k·p reduced mod n first so large products stay exact.
inline std::complex<double> twiddle(int64_t k, int64_t p, int64_t n, double sign) {
  const int64_t r = ((k * p) % n + n) % n;
  return std::polar(1.0, sign * 2.0 * M_PI * static_cast<double>(r) / static_cast<double>(n));
}

// x: [B, I, R, C], weight: [I, O, mx, my/2 + 1, 2] (kx index = kx + mx/2). Returns [B, O, R, C]
// in double.
inline torch::Tensor naive_spectral_conv2d(const torch::Tensor& x_in, const torch::Tensor& w_in) {
  const torch::Tensor x = x_in.to(torch::kDouble).contiguous();
  const torch::Tensor w = w_in.to(torch::kDouble).contiguous();
  const int64_t B = x.size(0), I = x.size(1), R = x.size(2), C = x.size(3);
  const int64_t O = w.size(1), mx = w.size(2), my = 2 * (w.size(3) - 1);
  auto xa = x.accessor<double, 4>();
  auto wa = w.accessor<double, 5>();
  torch::Tensor y = torch::zeros({B, O, R, C}, torch::kDouble);
  auto ya = y.accessor<double, 4>();
  for (int64_t row = 0; row < R; ++row) {
    const int64_t kx = signed_frequency(row, R);
    if (kx < -mx / 2 || kx >= mx / 2) continue;
    for (int64_t ky = 0; ky <= C / 2 && ky <= my / 2; ++ky) {
      // Columns other than 0 and C/2 stand for themselves and their conjugate mirror.
      const double multiplicity = (ky == 0 || 2 * ky == C) ? 1.0 : 2.0;
      std::vector<std::complex<double>> x_hat(B * I), y_hat(B * O);
      for (int64_t b = 0; b < B; ++b)
        for (int64_t i = 0; i < I; ++i) {
          std::complex<double> sum = 0;
          for (int64_t r = 0; r < R; ++r)
            for (int64_t c = 0; c < C; ++c) sum += xa[b][i][r][c] * twiddle(kx, r, R, -1) * twiddle(ky, c, C, -1);
          x_hat[b * I + i] = sum / static_cast<double>(R * C);
        }
      for (int64_t i = 0; i < I; ++i)
        for (int64_t o = 0; o < O; ++o) {
          const std::complex<double> w_io(wa[i][o][kx + mx / 2][ky][0], wa[i][o][kx + mx / 2][ky][1]);
          for (int64_t b = 0; b < B; ++b) y_hat[b * O + o] += x_hat[b * I + i] * w_io;
        }
      for (int64_t b = 0; b < B; ++b)
        for (int64_t o = 0; o < O; ++o)
          for (int64_t r = 0; r < R; ++r)
            for (int64_t c = 0; c < C; ++c)
              ya[b][o][r][c] +=
                  multiplicity * std::real(y_hat[b * O + o] * twiddle(kx, r, R, 1) * twiddle(ky, c, C, 1));
    }
  }
  return y;
}

// max |a − b| / max |b|.
inline double relative_error(const torch::Tensor& a, const torch::Tensor& b) {
  const torch::Tensor ad = a.to(torch::kDouble), bd = b.to(torch::kDouble);
  return (ad - bd).abs().max().item<double>() / bd.abs().max().item<double>();
}

}  // namespace fnopt::test
