// The FFTW plan cache and per-thread scratch under concurrency: plans created from several
// threads at once, and channels split across LibTorch's intra-op threads.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <thread>
#include <vector>

#include <fnopt/fno/spectral_conv2d.hpp>
#include "naive_spectral_conv.hpp"

namespace fnopt {
namespace {

TEST(SpectralConvThreads, ConcurrentCallsOnNewShapesAgreeWithTorchFft) {
  // Shapes no other test uses, so their plans are created here, concurrently.
  const std::vector<int64_t> sizes = {40, 41, 42, 43, 44, 45};
  std::vector<double> errors(sizes.size() * 2);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < errors.size(); ++t)
    threads.emplace_back([&, t] {
      const int64_t n = sizes[t % sizes.size()];
      const torch::Tensor x = torch::randn({2, 3, n, n + 3});
      const torch::Tensor w = torch::randn({3, 2, 8, 5, 2});
      errors[t] = test::relative_error(spectral_conv2d(x, w), spectral_conv2d_torchfft(x, w));
    });
  for (auto& thread : threads) thread.join();
  for (const double e : errors) EXPECT_LE(e, 1e-5);
}

TEST(SpectralConvThreads, IntraOpThreadsGiveTheSameResultAsOne) {
  torch::manual_seed(9);
  const torch::Tensor x = torch::randn({3, 16, 33, 20}).requires_grad_(true);
  const torch::Tensor w = torch::randn({16, 8, 8, 5, 2}).requires_grad_(true);
  const torch::Tensor probe = torch::randn({3, 8, 33, 20});
  const int previous = torch::get_num_threads();
  const auto run = [&](int threads) {
    torch::set_num_threads(threads);
    x.mutable_grad() = torch::Tensor();
    w.mutable_grad() = torch::Tensor();
    const torch::Tensor y = spectral_conv2d(x, w);
    (y * probe).sum().backward();
    return std::vector<torch::Tensor>{y.detach(), x.grad().clone(), w.grad().clone()};
  };
  const auto one = run(1);
  const auto two = run(2);
  torch::set_num_threads(previous);
  for (size_t k = 0; k < one.size(); ++k) EXPECT_TRUE(torch::allclose(one[k], two[k]));
}

}  // namespace
}  // namespace fnopt
