// The FFTW spectral convolution against a naive DFT and against the torch::fft version.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <tuple>
#include <vector>

#include <fnopt/fno/spectral_conv2d.hpp>
#include <fnopt/util/error.hpp>
#include "naive_spectral_conv.hpp"

namespace fnopt {
namespace {

// Odd, even, non-square grids, and grids with fewer points than the 8 × 8 modes.
const std::vector<std::tuple<int64_t, int64_t>> kGrids = {{32, 32}, {33, 31}, {64, 48}, {100, 100},
                                                          {6, 6},   {5, 7},   {1, 1}};

// Batch 2, 3 → 2 channels, modes 8 × 8, random input and weights.
std::tuple<torch::Tensor, torch::Tensor> random_case(int64_t rows, int64_t cols, torch::Dtype dtype) {
  torch::manual_seed(rows * 1000 + cols);
  return {torch::randn({2, 3, rows, cols}, dtype), torch::randn({3, 2, 8, 5, 2}, dtype)};
}

TEST(SpectralConv, FloatMatchesNaiveDftAndTorchFft) {
  for (const auto& [rows, cols] : kGrids) {
    SCOPED_TRACE(std::to_string(rows) + "x" + std::to_string(cols));
    const auto [x, w] = random_case(rows, cols, torch::kFloat);
    const torch::Tensor y = spectral_conv2d(x, w);
    EXPECT_EQ(y.scalar_type(), torch::kFloat);
    EXPECT_EQ(y.sizes(), torch::IntArrayRef({2, 2, rows, cols}));
    EXPECT_LE(test::relative_error(y, test::naive_spectral_conv2d(x, w)), 1e-5);
    EXPECT_LE(test::relative_error(y, spectral_conv2d_torchfft(x, w)), 1e-5);
  }
}

TEST(SpectralConv, DoubleMatchesNaiveDftAndTorchFft) {
  for (const auto& [rows, cols] : kGrids) {
    SCOPED_TRACE(std::to_string(rows) + "x" + std::to_string(cols));
    const auto [x, w] = random_case(rows, cols, torch::kDouble);
    const torch::Tensor naive = test::naive_spectral_conv2d(x, w);
    EXPECT_LE(test::relative_error(spectral_conv2d(x, w), naive), 1e-12);
    EXPECT_LE(test::relative_error(spectral_conv2d_torchfft(x, w), naive), 1e-12);
  }
}

TEST(SpectralConv, NonContiguousInputIsHandled) {
  torch::manual_seed(3);
  const torch::Tensor x = torch::randn({2, 3, 20, 24}, torch::kDouble).transpose(2, 3);
  const torch::Tensor w = torch::randn({3, 2, 8, 5, 2}, torch::kDouble);
  EXPECT_LE(test::relative_error(spectral_conv2d(x, w), test::naive_spectral_conv2d(x, w)), 1e-12);
}

TEST(SpectralConv, ModuleUsesBothBackendsAlike) {
  torch::manual_seed(4);
  SpectralConv2d layer(SpectralConv2dOptions(4, 3).modes_x(6).modes_y(4));
  EXPECT_EQ(layer->weight.sizes(), torch::IntArrayRef({4, 3, 6, 3, 2}));
  const torch::Tensor x = torch::randn({1, 4, 17, 12});
  EXPECT_LE(
      test::relative_error(layer->forward(x, SpectralBackend::fftw), layer->forward(x, SpectralBackend::torch_fft)),
      1e-5);
}

TEST(SpectralConv, MismatchedShapesAreUserErrors) {
  const torch::Tensor w = torch::randn({3, 2, 8, 5, 2});
  EXPECT_THROW(spectral_conv2d(torch::randn({1, 4, 8, 8}), w), Error);
  EXPECT_THROW(spectral_conv2d(torch::randn({4, 8, 8}), w), Error);
  EXPECT_THROW(spectral_conv2d(torch::randn({1, 3, 8, 8}), torch::randn({3, 2, 7, 5, 2})), Error);
  EXPECT_THROW(spectral_conv2d(torch::randn({1, 3, 8, 8}, torch::kDouble), w), Error);
}

}  // namespace
}  // namespace fnopt
