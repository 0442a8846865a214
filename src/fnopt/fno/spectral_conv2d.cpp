#include <fnopt/fno/spectral_conv2d.hpp>

#include <cmath>

#include <fnopt/fno/mode_mixing.hpp>
#include <fnopt/fno/spectral_transform.hpp>
#include <fnopt/fno/spectral_weight.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

using fno::KeptModes;

KeptModes modes_from(const torch::autograd::AutogradContext* ctx) {
  KeptModes m;
  const auto& d = ctx->saved_data;
  m.rows = d.at("rows").toInt();
  m.cols = d.at("cols").toInt();
  m.lowest_row_freq = d.at("lowest_row_freq").toInt();
  m.kept_rows = d.at("kept_rows").toInt();
  m.kept_cols = d.at("kept_cols").toInt();
  m.weight_row_offset = d.at("weight_row_offset").toInt();
  return m;
}

void save_modes(torch::autograd::AutogradContext* ctx, const KeptModes& m) {
  auto& d = ctx->saved_data;
  d["rows"] = m.rows;
  d["cols"] = m.cols;
  d["lowest_row_freq"] = m.lowest_row_freq;
  d["kept_rows"] = m.kept_rows;
  d["kept_cols"] = m.kept_cols;
  d["weight_row_offset"] = m.weight_row_offset;
}

// Weight of each kept column in the real output, [1, 1, 1, kept_cols, 1]: 1 for the
// self-conjugate columns, 2 for the others (each stands for itself and its conjugate).
torch::Tensor column_multiplicity(const KeptModes& m, const torch::TensorOptions& options) {
  torch::Tensor w = torch::full({m.kept_cols}, 2.0, options);
  for (int64_t ky = 0; ky < m.kept_cols; ++ky)
    if (m.self_conjugate_col(ky)) w[ky] = 1.0;
  return w.view({1, 1, 1, m.kept_cols, 1});
}

// Forward: x̂ = F x / (RC), ŷ_o = Σ_i x̂_i W_io, y = S ŷ, with F = analyze (the DFT at the kept
// modes) and S = synthesize, which counts every column but the self-conjugate ones twice:
// S = Fᴴ α, Fᴴ the adjoint of F for ⟨a, b⟩ = Re Σ a·conj(b), α the column multiplicity.
// For g = ∂L/∂y and ĝ = F g (unnormalised):
//   ∂L/∂ŷ_o = α ĝ_o,   ∂L/∂W_io = Σ_b α ĝ_o conj(x̂_i),
//   ∂L/∂x_i = Fᴴ(Σ_o α ĝ_o conj(W_io)) / (RC) = S(Σ_o ĝ_o conj(W_io)) / (RC).
// So the backward pass is one analyze and one synthesize, the same FFTs as the forward.
class SpectralConv2dFunction : public torch::autograd::Function<SpectralConv2dFunction> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& x,
                               const torch::Tensor& weight) {
    const KeptModes m = fno::kept_modes_for(x, weight);
    const int64_t batch = x.size(0), in = weight.size(0), out = weight.size(1);
    const torch::Tensor w = fno::kept_weight(weight, m).reshape({in, out, m.kept_count(), 2});
    const torch::Tensor x_hat = fno::analyze(x.reshape({batch * in, m.rows, m.cols}), m, 1.0 / (m.rows * m.cols))
                                    .view({batch, in, m.kept_count(), 2});
    const torch::Tensor y_hat = fno::mix_modes(x_hat, w);
    save_modes(ctx, m);
    ctx->saved_data["x_hat"] = x_hat;
    ctx->save_for_backward({weight});
    return fno::synthesize(y_hat.view({batch * out, m.kept_rows, m.kept_cols, 2}), m, 1.0)
        .view({batch, out, m.rows, m.cols});
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list grad_outputs) {
    const KeptModes m = modes_from(ctx);
    const torch::Tensor weight = ctx->get_saved_variables()[0];
    const torch::Tensor x_hat = ctx->saved_data.at("x_hat").toTensor();
    const int64_t batch = x_hat.size(0), in = weight.size(0), out = weight.size(1);
    const torch::Tensor g_hat = fno::analyze(grad_outputs[0].reshape({batch * out, m.rows, m.cols}), m, 1.0)
                                    .view({batch, out, m.kept_count(), 2});
    torch::Tensor grad_x, grad_weight;
    if (ctx->needs_input_grad(0)) {
      const torch::Tensor w = fno::kept_weight(weight, m).reshape({in, out, m.kept_count(), 2});
      const torch::Tensor h = fno::mix_modes_adjoint_input(g_hat, w);
      grad_x = fno::synthesize(h.view({batch * in, m.kept_rows, m.kept_cols, 2}), m, 1.0 / (m.rows * m.cols))
                   .view({batch, in, m.rows, m.cols});
    }
    if (ctx->needs_input_grad(1)) {
      const torch::Tensor alpha_g =
          g_hat.view({batch, out, m.kept_rows, m.kept_cols, 2}) * column_multiplicity(m, g_hat.options());
      const torch::Tensor kept_grad =
          fno::mix_modes_adjoint_weight(alpha_g.view({batch, out, m.kept_count(), 2}), x_hat)
              .view({in, out, m.kept_rows, m.kept_cols, 2});
      if (kept_grad.sizes() == weight.sizes()) {
        grad_weight = kept_grad;
      } else {
        grad_weight = torch::zeros_like(weight);
        fno::kept_weight(grad_weight, m).copy_(kept_grad);
      }
    }
    return {grad_x, grad_weight};
  }
};

}  // namespace

torch::Tensor spectral_conv2d(const torch::Tensor& x, const torch::Tensor& weight) {
  return SpectralConv2dFunction::apply(x, weight);
}

torch::Tensor spectral_conv2d(const torch::Tensor& x, const torch::Tensor& weight, SpectralBackend backend) {
  return backend == SpectralBackend::fftw ? spectral_conv2d(x, weight) : spectral_conv2d_torchfft(x, weight);
}

SpectralConv2dImpl::SpectralConv2dImpl(const SpectralConv2dOptions& options_) : options(options_) {
  require(options.in_channels() > 0 && options.out_channels() > 0, "spectral convolution",
          "channel counts must be positive");
  fno::kept_modes(1, 1, options.modes_x(), options.modes_y());  // validates the modes
  const double init_std = std::sqrt(1.0 / static_cast<double>(options.in_channels() + options.out_channels()));
  weight = register_parameter("weight", torch::randn({options.in_channels(), options.out_channels(), options.modes_x(),
                                                      options.modes_y() / 2 + 1, 2}) *
                                            init_std);
}

torch::Tensor SpectralConv2dImpl::forward(const torch::Tensor& x, SpectralBackend backend) {
  return spectral_conv2d(x, weight, backend);
}

}  // namespace fnopt
