#include <fnopt/fno/fno2d.hpp>

#include <chrono>
#include <cmath>
#include <sstream>
#include <string>

#include <fnopt/fno/pointwise_linear.hpp>
#include <fnopt/util/error.hpp>

namespace fnopt {
namespace {

void require_positive(int64_t value, const char* name) {
  require(value > 0, std::string("FNO2d option ") + name, "must be positive, got " + std::to_string(value));
}

void require_positive_even(int64_t value, const char* name) {
  require(value > 0 && value % 2 == 0, std::string("FNO2d option ") + name,
          "must be positive and even, got " + std::to_string(value));
}

// Channels i/R and j/C in [0, 1): the position on the unit torus, the same physical point at
// every resolution. [B, 2, R, C].
torch::Tensor grid_channels(int64_t batch, int64_t rows, int64_t cols, const torch::TensorOptions& options) {
  const torch::Tensor i =
      (torch::arange(rows, options) / static_cast<double>(rows)).view({1, 1, rows, 1}).expand({batch, 1, rows, cols});
  const torch::Tensor j =
      (torch::arange(cols, options) / static_cast<double>(cols)).view({1, 1, 1, cols}).expand({batch, 1, rows, cols});
  return torch::cat({i, j}, 1);
}

// Adds the time since the previous lap to a stage's total; does nothing when not profiling.
class StageClock {
 public:
  explicit StageClock(FNO2dStageTimes* times) : times_(times), last_(now()) {}
  void lap(double FNO2dStageTimes::*stage) {
    if (!times_) return;
    const auto t = now();
    times_->*stage += std::chrono::duration<double, std::milli>(t - last_).count();
    last_ = t;
  }

 private:
  static std::chrono::steady_clock::time_point now() { return std::chrono::steady_clock::now(); }
  FNO2dStageTimes* times_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace

void validate(const FNO2dOptions& o) {
  require_positive(o.in_channels(), "in_channels");
  require_positive(o.out_channels(), "out_channels");
  require_positive(o.width(), "width");
  require_positive(o.fourier_layers(), "fourier_layers");
  require_positive_even(o.modes_x(), "modes_x");
  require_positive_even(o.modes_y(), "modes_y");
  require_positive(o.lifting_channels(), "lifting_channels");
  require_positive(o.projection_channels(), "projection_channels");
  if (o.scale_head())
    require(o.scale_head_layer() >= 0 && o.scale_head_layer() < o.fourier_layers(), "FNO2d option scale_head_layer",
            "must name a Fourier layer in [0, " + std::to_string(o.fourier_layers()) + "), got " +
                std::to_string(o.scale_head_layer()));
  require(std::isfinite(o.padding_fraction()) && o.padding_fraction() >= 0 && o.padding_fraction() <= 1,
          "FNO2d option padding_fraction", "must be in [0, 1], got " + std::to_string(o.padding_fraction()));
}

FNO2dImpl::FNO2dImpl(const FNO2dOptions& options_) : options(options_) {
  validate(options);
  const int64_t width = options.width();
  lift_in_ = register_module("lift_in", torch::nn::Linear(options.in_channels() + 2, options.lifting_channels()));
  lift_out_ = register_module("lift_out", torch::nn::Linear(options.lifting_channels(), width));
  const auto spectral_options =
      SpectralConv2dOptions(width, width).modes_x(options.modes_x()).modes_y(options.modes_y());
  for (int64_t l = 0; l < options.fourier_layers(); ++l) {
    const std::string index = std::to_string(l);
    spectral_.push_back(register_module("spectral_" + index, SpectralConv2d(spectral_options)));
    skip_.push_back(register_module("skip_" + index, torch::nn::Linear(width, width)));
  }
  project_in_ = register_module("project_in", torch::nn::Linear(width, options.projection_channels()));
  project_out_ =
      register_module("project_out", torch::nn::Linear(options.projection_channels(), options.out_channels()));
  if (options.scale_head()) scale_head_ = register_module("scale_head", torch::nn::Linear(width, 1));
}

FNO2dOutput FNO2dImpl::forward(const torch::Tensor& x) { return run(x, nullptr); }

FNO2dOutput FNO2dImpl::forward_profiled(const torch::Tensor& x, FNO2dStageTimes& times) { return run(x, &times); }

FNO2dOutput FNO2dImpl::run(const torch::Tensor& x, FNO2dStageTimes* times) {
  using fno::pointwise_linear;
  validate(options);  // spectral_backend and padding_fraction may have changed since construction
  if (x.dim() != 4 || x.size(1) != options.in_channels()) {
    std::ostringstream got;
    got << x.sizes();
    throw Error("FNO2d input: must be [B, " + std::to_string(options.in_channels()) + ", R, C], got " + got.str());
  }
  const int64_t batch = x.size(0), rows = x.size(2), cols = x.size(3);
  StageClock clock(times);

  torch::Tensor h = torch::cat({x, grid_channels(batch, rows, cols, x.options())}, 1);
  h = pointwise_linear(torch::gelu(pointwise_linear(h, lift_in_)), lift_out_);
  clock.lap(&FNO2dStageTimes::lifting_ms);

  const int64_t pad_rows = static_cast<int64_t>(std::ceil(options.padding_fraction() * rows));
  const int64_t pad_cols = static_cast<int64_t>(std::ceil(options.padding_fraction() * cols));
  const bool padded = pad_rows > 0 || pad_cols > 0;
  const auto crop = [&](const torch::Tensor& t) {
    return padded ? t.narrow(2, pad_rows, rows).narrow(3, pad_cols, cols) : t;
  };
  if (padded) h = torch::constant_pad_nd(h, {pad_cols, pad_cols, pad_rows, pad_rows});

  FNO2dOutput out;
  const int64_t layers = options.fourier_layers();
  for (int64_t l = 0; l < layers; ++l) {
    clock.lap(&FNO2dStageTimes::other_ms);
    const torch::Tensor spectral = spectral_[l]->forward(h, options.spectral_backend());
    clock.lap(&FNO2dStageTimes::spectral_ms);
    h = spectral + pointwise_linear(h, skip_[l]);
    clock.lap(&FNO2dStageTimes::skip_ms);
    if (l + 1 < layers) h = torch::gelu(h);
    if (options.scale_head() && l == options.scale_head_layer()) out.scale = scale_head_->forward(crop(h).amax({2, 3}));
  }
  h = crop(h);
  clock.lap(&FNO2dStageTimes::other_ms);
  out.field = pointwise_linear(torch::gelu(pointwise_linear(h, project_in_)), project_out_);
  clock.lap(&FNO2dStageTimes::projection_ms);
  return out;
}

}  // namespace fnopt
