#include <fnopt/fno/mode_mixing.hpp>

#include <ATen/Parallel.h>

namespace fnopt::fno {
namespace {

// acc[m] += a[m] · b[m] (conjugate_b: · conj(b[m])) over M complex numbers, directly on the
// interleaved re/im pairs of the weight layout, so no split copy of the weights is made. The
// callers order their loops so that each weight block (1.3 MB per layer at width 64, modes 8)
// is read once for the whole batch.
template <bool conjugate_b, typename Real>
inline void multiply_add(Real* __restrict acc, const Real* __restrict a, const Real* __restrict b, int64_t modes) {
  const Real sign = conjugate_b ? Real(-1) : Real(1);
  for (int64_t m = 0; m < 2 * modes; m += 2) {
    const Real bi = sign * b[m + 1];
    acc[m] += a[m] * b[m] - a[m + 1] * bi;
    acc[m + 1] += a[m] * bi + a[m + 1] * b[m];
  }
}

}  // namespace

torch::Tensor mix_modes(const torch::Tensor& x_in, const torch::Tensor& w_in) {
  const torch::Tensor x = x_in.contiguous(), w = w_in.contiguous();
  const int64_t batch = x.size(0), in = x.size(1), out = w.size(1), modes = x.size(2);
  torch::Tensor y = torch::zeros({batch, out, modes, 2}, x.options());
  AT_DISPATCH_FLOATING_TYPES(x.scalar_type(), "fnopt_mix_modes", [&] {
    const scalar_t* xp = x.data_ptr<scalar_t>();
    const scalar_t* wp = w.data_ptr<scalar_t>();
    scalar_t* yp = y.data_ptr<scalar_t>();
    at::parallel_for(0, out, 4, [&](int64_t o_begin, int64_t o_end) {
      for (int64_t i = 0; i < in; ++i)
        for (int64_t o = o_begin; o < o_end; ++o)
          for (int64_t b = 0; b < batch; ++b)
            multiply_add<false>(yp + (b * out + o) * 2 * modes, xp + (b * in + i) * 2 * modes,
                                wp + (i * out + o) * 2 * modes, modes);
    });
  });
  return y;
}

torch::Tensor mix_modes_adjoint_input(const torch::Tensor& g_in, const torch::Tensor& w_in) {
  const torch::Tensor g = g_in.contiguous(), w = w_in.contiguous();
  const int64_t batch = g.size(0), out = g.size(1), in = w.size(0), modes = g.size(2);
  torch::Tensor h = torch::zeros({batch, in, modes, 2}, g.options());
  AT_DISPATCH_FLOATING_TYPES(g.scalar_type(), "fnopt_mix_modes_adjoint_input", [&] {
    const scalar_t* gp = g.data_ptr<scalar_t>();
    const scalar_t* wp = w.data_ptr<scalar_t>();
    scalar_t* hp = h.data_ptr<scalar_t>();
    at::parallel_for(0, in, 4, [&](int64_t i_begin, int64_t i_end) {
      for (int64_t i = i_begin; i < i_end; ++i)
        for (int64_t o = 0; o < out; ++o)
          for (int64_t b = 0; b < batch; ++b)
            multiply_add<true>(hp + (b * in + i) * 2 * modes, gp + (b * out + o) * 2 * modes,
                               wp + (i * out + o) * 2 * modes, modes);
    });
  });
  return h;
}

torch::Tensor mix_modes_adjoint_weight(const torch::Tensor& g_in, const torch::Tensor& x_in) {
  const torch::Tensor g = g_in.contiguous(), x = x_in.contiguous();
  const int64_t batch = g.size(0), out = g.size(1), in = x.size(1), modes = g.size(2);
  torch::Tensor gw = torch::zeros({in, out, modes, 2}, g.options());
  AT_DISPATCH_FLOATING_TYPES(g.scalar_type(), "fnopt_mix_modes_adjoint_weight", [&] {
    const scalar_t* gp = g.data_ptr<scalar_t>();
    const scalar_t* xp = x.data_ptr<scalar_t>();
    scalar_t* gwp = gw.data_ptr<scalar_t>();
    at::parallel_for(0, in, 4, [&](int64_t i_begin, int64_t i_end) {
      for (int64_t i = i_begin; i < i_end; ++i)
        for (int64_t o = 0; o < out; ++o)
          for (int64_t b = 0; b < batch; ++b)
            multiply_add<true>(gwp + (i * out + o) * 2 * modes, gp + (b * out + o) * 2 * modes,
                               xp + (b * in + i) * 2 * modes, modes);
    });
  });
  return gw;
}

}  // namespace fnopt::fno
