// Gradients of the FFTW spectral convolution's autograd Function: against central finite
// differences in double, and against LibTorch's autograd through the torch::fft version.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <functional>
#include <tuple>

#include <fnopt/fno/spectral_conv2d.hpp>
#include "naive_spectral_conv.hpp"

namespace fnopt {
namespace {

struct GradCase {
  int64_t rows, cols, modes_x, modes_y;
};

// A scalar loss with a random probe, so every output entry matters: L = Σ y ⊙ probe.
double loss(const torch::Tensor& x, const torch::Tensor& w, const torch::Tensor& probe) {
  return (spectral_conv2d(x, w) * probe).sum().item<double>();
}

// Central difference of the loss along every entry of `t` (x or w, perturbed in place).
torch::Tensor finite_difference(torch::Tensor t, const std::function<double()>& f) {
  const double h = 1e-6;
  torch::Tensor grad = torch::zeros_like(t);
  auto flat = t.view({-1});
  auto g = grad.view({-1});
  for (int64_t k = 0; k < flat.numel(); ++k) {
    const double v = flat[k].item<double>();
    flat[k] = v + h;
    const double up = f();
    flat[k] = v - h;
    const double down = f();
    flat[k] = v;
    g[k] = (up - down) / (2 * h);
  }
  return grad;
}

// Odd and even sizes; the even-column Nyquist mode kept (cols 8, modes 8) or not; grids
// smaller than the modes (4 rows with modes 8: the even-row Nyquist kx = −2 is kept).
TEST(SpectralConvGradient, MatchesFiniteDifferencesInDouble) {
  for (const GradCase& c : {GradCase{4, 8, 8, 8}, GradCase{7, 6, 4, 4}, GradCase{6, 9, 4, 6}, GradCase{3, 3, 8, 8}}) {
    SCOPED_TRACE(std::to_string(c.rows) + "x" + std::to_string(c.cols) + " modes " + std::to_string(c.modes_x) + "x" +
                 std::to_string(c.modes_y));
    torch::manual_seed(c.rows * 100 + c.cols);
    torch::Tensor x = torch::randn({2, 2, c.rows, c.cols}, torch::kDouble);
    torch::Tensor w = torch::randn({2, 3, c.modes_x, c.modes_y / 2 + 1, 2}, torch::kDouble);
    const torch::Tensor probe = torch::randn({2, 3, c.rows, c.cols}, torch::kDouble);

    const torch::Tensor xg = x.clone().requires_grad_(true), wg = w.clone().requires_grad_(true);
    (spectral_conv2d(xg, wg) * probe).sum().backward();

    torch::NoGradGuard no_grad;
    const auto f = [&] { return loss(x, w, probe); };
    const torch::Tensor fd_x = finite_difference(x, f);
    const torch::Tensor fd_w = finite_difference(w, f);
    EXPECT_LE(test::relative_error(xg.grad(), fd_x), 1e-7);
    EXPECT_LE(test::relative_error(wg.grad(), fd_w), 1e-7);
  }
}

// Input and weight gradients of both implementations for the same upstream gradient.
std::tuple<torch::Tensor, torch::Tensor, torch::Tensor, torch::Tensor> both_gradients(int64_t rows, int64_t cols,
                                                                                      torch::Dtype dtype) {
  torch::manual_seed(rows * 7 + cols);
  const torch::Tensor x = torch::randn({3, 4, rows, cols}, dtype);
  const torch::Tensor w = torch::randn({4, 5, 8, 5, 2}, dtype);
  const torch::Tensor probe = torch::randn({3, 5, rows, cols}, dtype);
  const torch::Tensor x1 = x.clone().requires_grad_(true), w1 = w.clone().requires_grad_(true);
  const torch::Tensor x2 = x.clone().requires_grad_(true), w2 = w.clone().requires_grad_(true);
  (spectral_conv2d(x1, w1) * probe).sum().backward();
  (spectral_conv2d_torchfft(x2, w2) * probe).sum().backward();
  return {x1.grad(), x2.grad(), w1.grad(), w2.grad()};
}

TEST(SpectralConvGradient, MatchesAutogradThroughTorchFft) {
  for (const auto& [rows, cols] : {std::pair<int64_t, int64_t>{33, 31}, {32, 32}, {6, 6}}) {
    SCOPED_TRACE(std::to_string(rows) + "x" + std::to_string(cols));
    const auto [gx, gx_ref, gw, gw_ref] = both_gradients(rows, cols, torch::kDouble);
    EXPECT_LE(test::relative_error(gx, gx_ref), 1e-12);
    EXPECT_LE(test::relative_error(gw, gw_ref), 1e-12);
    const auto [fx, fx_ref, fw, fw_ref] = both_gradients(rows, cols, torch::kFloat);
    EXPECT_LE(test::relative_error(fx, fx_ref), 1e-5);
    EXPECT_LE(test::relative_error(fw, fw_ref), 1e-5);
  }
}

TEST(SpectralConvGradient, OnlyRequestedGradientsAreComputed) {
  const torch::Tensor x = torch::randn({1, 2, 8, 8}, torch::kDouble).requires_grad_(true);
  const torch::Tensor w = torch::randn({2, 2, 4, 3, 2}, torch::kDouble);
  spectral_conv2d(x, w).sum().backward();
  EXPECT_TRUE(x.grad().defined());
  EXPECT_FALSE(w.grad().defined());
}

}  // namespace
}  // namespace fnopt
