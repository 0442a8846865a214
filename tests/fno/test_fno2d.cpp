// The FNO2d model: FNOpt's defaults, shapes, option validation, scale head, padding, and the
// two spectral backends agreeing in values and gradients.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <string>

#include <fnopt/fno/fno2d.hpp>
#include <fnopt/fno/pointwise_linear.hpp>
#include <fnopt/util/error.hpp>
#include "naive_spectral_conv.hpp"

namespace fnopt {
namespace {

TEST(FNO2d, DefaultsAreFnoptsConfiguration) {
  const FNO2dOptions o;
  EXPECT_EQ(o.in_channels(), 3);
  EXPECT_EQ(o.out_channels(), 1);
  EXPECT_EQ(o.width(), 64);
  EXPECT_EQ(o.fourier_layers(), 4);
  EXPECT_EQ(o.modes_x(), 8);
  EXPECT_EQ(o.modes_y(), 8);
  EXPECT_EQ(o.lifting_channels(), 256);
  EXPECT_EQ(o.projection_channels(), 64);
  EXPECT_TRUE(o.scale_head());
  EXPECT_EQ(o.scale_head_layer(), 1);
  EXPECT_EQ(o.padding_fraction(), 0.0);
  EXPECT_EQ(o.spectral_backend(), SpectralBackend::fftw);

  FNO2d model;
  const auto params = model->named_parameters();
  EXPECT_EQ(params["lift_in.weight"].sizes(), torch::IntArrayRef({256, 5}));
  EXPECT_EQ(params["lift_out.weight"].sizes(), torch::IntArrayRef({64, 256}));
  EXPECT_EQ(params["spectral_3.weight"].sizes(), torch::IntArrayRef({64, 64, 8, 5, 2}));
  EXPECT_EQ(params["skip_3.weight"].sizes(), torch::IntArrayRef({64, 64}));
  EXPECT_EQ(params["project_in.weight"].sizes(), torch::IntArrayRef({64, 64}));
  EXPECT_EQ(params["project_out.weight"].sizes(), torch::IntArrayRef({1, 64}));
  EXPECT_EQ(params["scale_head.weight"].sizes(), torch::IntArrayRef({1, 64}));
}

TEST(FNO2d, OutputShapesOnAnyGrid) {
  FNO2d model(FNO2dOptions().width(8).lifting_channels(16).projection_channels(8).out_channels(3));
  torch::NoGradGuard no_grad;
  for (const auto& [rows, cols] : {std::pair<int64_t, int64_t>{32, 32}, {33, 20}, {6, 6}, {1, 5}}) {
    const FNO2dOutput out = model->forward(torch::randn({2, 3, rows, cols}));
    EXPECT_EQ(out.field.sizes(), torch::IntArrayRef({2, 3, rows, cols}));
    EXPECT_EQ(out.scale.sizes(), torch::IntArrayRef({2, 1}));
    EXPECT_TRUE(torch::isfinite(out.field).all().item<bool>());
  }
}

TEST(FNO2d, WithoutScaleHeadTheScaleIsUndefined) {
  FNO2d model(FNO2dOptions().width(8).lifting_channels(8).projection_channels(8).scale_head(false));
  EXPECT_FALSE(model->forward(torch::randn({1, 3, 8, 8})).scale.defined());
  EXPECT_EQ(model->named_parameters().find("scale_head.weight"), nullptr);
}

void expect_option_error(const FNO2dOptions& options, const std::string& message) {
  try {
    FNO2d model(options);
    ADD_FAILURE() << "no error for " << message;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(FNO2d, InvalidOptionsAreRejectedByName) {
  expect_option_error(FNO2dOptions().width(0), "FNO2d option width: must be positive, got 0");
  expect_option_error(FNO2dOptions().in_channels(-1), "option in_channels");
  expect_option_error(FNO2dOptions().fourier_layers(0), "option fourier_layers");
  expect_option_error(FNO2dOptions().lifting_channels(0), "option lifting_channels");
  expect_option_error(FNO2dOptions().projection_channels(0), "option projection_channels");
  expect_option_error(FNO2dOptions().modes_x(7), "option modes_x: must be positive and even");
  expect_option_error(FNO2dOptions().modes_y(0), "option modes_y");
  expect_option_error(FNO2dOptions().scale_head_layer(4),
                      "scale_head_layer: must name a Fourier layer in [0, 4), got 4");
  expect_option_error(FNO2dOptions().padding_fraction(-0.1), "option padding_fraction");
  // The head layer does not matter without a head.
  EXPECT_NO_THROW(validate(FNO2dOptions().scale_head(false).scale_head_layer(9)));
}

TEST(FNO2d, WrongInputChannelsAreAUserError) {
  FNO2d model(FNO2dOptions().width(8).lifting_channels(8).projection_channels(8));
  try {
    model->forward(torch::randn({1, 2, 8, 8}));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("must be [B, 3, R, C], got [1, 2, 8, 8]"), std::string::npos) << e.what();
  }
}

TEST(FNO2d, ScaleHeadReadsOnlyItsLayerAndThoseBefore) {
  torch::manual_seed(1);
  FNO2d model(FNO2dOptions().width(8).lifting_channels(8).projection_channels(8));
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({2, 3, 16, 16});
  const FNO2dOutput before = model->forward(x);
  model->named_parameters()["spectral_2.weight"].mul_(3);
  const FNO2dOutput after_later_layer = model->forward(x);
  EXPECT_TRUE(torch::equal(before.scale, after_later_layer.scale));
  EXPECT_FALSE(torch::allclose(before.field, after_later_layer.field));
  model->named_parameters()["spectral_1.weight"].mul_(3);
  EXPECT_FALSE(torch::allclose(before.scale, model->forward(x).scale));
}

TEST(FNO2d, PaddingKeepsTheOutputGridAndChangesTheResult) {
  torch::manual_seed(2);
  FNO2d model(FNO2dOptions().width(8).lifting_channels(8).projection_channels(8));
  torch::NoGradGuard no_grad;
  const torch::Tensor x = torch::randn({1, 3, 20, 13});
  const FNO2dOutput plain = model->forward(x);
  model->options.padding_fraction(0.25);
  const FNO2dOutput padded = model->forward(x);
  EXPECT_EQ(padded.field.sizes(), plain.field.sizes());
  EXPECT_FALSE(torch::allclose(padded.field, plain.field));
  model->options.spectral_backend(SpectralBackend::torch_fft);
  EXPECT_LE(test::relative_error(model->forward(x).field, padded.field), 1e-5);
}

TEST(FNO2d, BackendsAgreeInOutputsAndParameterGradients) {
  torch::manual_seed(3);
  FNO2d model;
  const torch::Tensor x = torch::randn({3, 3, 24, 20});
  const auto run = [&](SpectralBackend backend) {
    model->zero_grad();
    model->options.spectral_backend(backend);
    const FNO2dOutput out = model->forward(x);
    (out.field.square().sum() + out.scale.sum()).backward();
    std::vector<torch::Tensor> grads;
    for (const auto& p : model->parameters()) grads.push_back(p.grad().clone());
    return std::make_pair(out, grads);
  };
  const auto [fftw, fftw_grads] = run(SpectralBackend::fftw);
  const auto [tfft, tfft_grads] = run(SpectralBackend::torch_fft);
  EXPECT_LE(test::relative_error(fftw.field, tfft.field), 1e-5);
  EXPECT_LE(test::relative_error(fftw.scale, tfft.scale), 1e-5);
  ASSERT_EQ(fftw_grads.size(), tfft_grads.size());
  for (size_t k = 0; k < fftw_grads.size(); ++k) {
    EXPECT_GT(fftw_grads[k].abs().max().item<double>(), 0) << "parameter " << k;
    EXPECT_LE(test::relative_error(fftw_grads[k], tfft_grads[k]), 1e-4) << "parameter " << k;
  }
}

TEST(FNO2d, RunsInDouble) {
  torch::manual_seed(4);
  FNO2d model(FNO2dOptions().width(8).lifting_channels(8).projection_channels(8));
  model->to(torch::kDouble);
  const torch::Tensor x = torch::randn({1, 3, 10, 12}, torch::kDouble);
  const FNO2dOutput fftw = model->forward(x);
  model->options.spectral_backend(SpectralBackend::torch_fft);
  EXPECT_EQ(fftw.field.scalar_type(), torch::kDouble);
  EXPECT_LE(test::relative_error(fftw.field, model->forward(x).field), 1e-12);
}

TEST(PointwiseLinear, IsAOneByOneConvolution) {
  torch::manual_seed(5);
  torch::nn::Linear linear(5, 7);
  const torch::Tensor x = torch::randn({2, 5, 9, 4});
  const torch::Tensor reference = torch::conv2d(x, linear->weight.view({7, 5, 1, 1}), linear->bias);
  EXPECT_LE(test::relative_error(fno::pointwise_linear(x, linear), reference), 1e-6);
}

}  // namespace
}  // namespace fnopt
